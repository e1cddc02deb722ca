//! Output formats shared by the subcommands, and the checked, atomic
//! writing of output files: paths are checked before any work starts and
//! files appear only complete (temporary file, then rename); which paths
//! are replaced, followed, written through or refused is
//! [`super::output_guard`]'s.

use super::cleanup;
use super::output_guard::{self as guard, Target};
use super::CliError;
use crate::provenance::{Inputs, Provenance};
use clap::ValueEnum;
use std::io::Write;
use std::path::{Path, PathBuf};

/// `--format` of the commands with a per-case table (compare).
#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// Aligned console table, to significant figures.
    Table,
    /// JSON on stdout, full precision.
    Json,
    /// CSV on stdout, one row per case, plain decimals.
    Csv,
}

/// `--format` of the commands whose output has no rows for a CSV.
#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum TableOrJson {
    /// Console text, to significant figures.
    Table,
    /// JSON on stdout, full precision.
    Json,
}

/// `--format` of the commands whose main table has rows (diagnose, fit,
/// audit): the CSV is that table, full precision, after the provenance
/// block's `#` lines.
#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum TableJsonCsv {
    /// Console text, to significant figures.
    Table,
    /// JSON on stdout, full precision.
    Json,
    /// CSV on stdout: the command's main table, one row per line, full precision.
    Csv,
}

/// `rows` as CSV on stdout (provenance block first); an empty table still
/// gets its provenance, so a script reading it sees where it came from.
pub fn print_csv<T: serde::Serialize>(rows: &[T], inputs: &Inputs) -> Result<(), CliError> {
    let mut bytes = Vec::new();
    if rows.is_empty() {
        bytes.extend(Provenance::capture(inputs).comment_block().into_bytes());
    } else {
        write_csv_rows(rows, &mut bytes, inputs)?;
    }
    use std::io::Write;
    super::stdout::stdout_written(std::io::stdout().lock().write_all(&bytes), "the CSV")
}

/// The help of every `--format`.
pub const FORMAT_HELP: &str = "Output format on stdout";

/// Default output directories: all under one `swimbot-out/` in the working
/// directory, `swimbot-out/`, so that no run litters a source tree (it is
/// git-ignored).
/// `compare`'s HTML report.
pub const DEFAULT_REPORT_DIR: &str = "swimbot-out/report";
/// `sim`'s CSV and SVG.
pub const DEFAULT_SIM_DIR: &str = "swimbot-out/sim";

/// Print JSON to stdout (serialisation of our own types cannot fail). An
/// object gains the run's provenance as its first key, `swimbot`
/// ([`crate::provenance`], naming `inputs`); a list (`effects`) is printed
/// as it is.
pub fn print_json<T: serde::Serialize>(value: &T, inputs: &Inputs) {
    // Keys stay in their declared order: the value is not rebuilt as a
    // (sorted) `serde_json::Value`, only checked for being an object.
    let is_object = serde_json::to_value(value).is_ok_and(|v| v.is_object());
    let text = if is_object {
        serde_json::to_string_pretty(&crate::provenance::with_provenance(value, inputs))
    } else {
        serde_json::to_string_pretty(value)
    };
    println!("{}", text.expect("serialisable"));
}

/// Rows of flat structs as CSV with every number in the one CSV style
/// ([`crate::format::csv_f64`]): the csv crate's own float writer switches
/// to `1e-7` notation for small and large values. Columns in the struct's
/// declared order; `None` is an empty cell. The provenance comes first, as
/// `#` comment lines (pandas: `read_csv(..., comment="#")`).
pub fn write_csv_rows<T: serde::Serialize>(
    rows: &[T],
    out: impl std::io::Write,
    inputs: &Inputs,
) -> Result<(), CliError> {
    // Our rows always serialise; what fails is the write (a full disk, a
    // closed device), the user's to fix: exit 2, as every output.
    let fail = |e: &dyn std::fmt::Display| CliError::input(format!("cannot write the CSV: {e}"));
    let Some(first) = rows.first() else {
        return Ok(());
    };
    // The header, in declared order, from the csv crate's serde support.
    let mut probe = csv::Writer::from_writer(Vec::new());
    probe.serialize(first).map_err(|e| fail(&e))?;
    let bytes = probe.into_inner().map_err(|e| fail(&e))?;
    let header: Vec<String> = csv::Reader::from_reader(bytes.as_slice())
        .headers()
        .map_err(|e| fail(&e))?
        .iter()
        .map(str::to_string)
        .collect();
    let mut out = out;
    out.write_all(Provenance::capture(inputs).comment_block().as_bytes())
        .map_err(|e| fail(&e))?;
    let mut w = csv::Writer::from_writer(out);
    w.write_record(&header).map_err(|e| fail(&e))?;
    for row in rows {
        let v = serde_json::to_value(row).map_err(|e| fail(&e))?;
        let cells = header.iter().map(|h| match v.get(h) {
            Some(serde_json::Value::Number(n)) if n.is_f64() => {
                crate::format::csv_f64(n.as_f64().unwrap_or(f64::NAN))
            }
            Some(serde_json::Value::Number(n)) => n.to_string(),
            Some(serde_json::Value::String(s)) => s.clone(),
            Some(serde_json::Value::Bool(b)) => b.to_string(),
            _ => String::new(),
        });
        w.write_record(cells).map_err(|e| fail(&e))?;
    }
    w.flush().map_err(|e| fail(&e))
}

/// Refuse to print a result with a non-finite number (JSON would show it as
/// `null`, a table as NaN): valid input that yields one is a fault of the
/// computation (exit 1), reported with the number's path.
pub fn check_finite<T: serde::Serialize + ?Sized>(what: &str, value: &T) -> Result<(), CliError> {
    match super::finite::first_non_finite(value) {
        None => Ok(()),
        Some(at) => Err(CliError::failure(format!(
            "the {what} has a non-finite number ({at}); nothing was printed"
        ))),
    }
}

/// `Some(x)` formatted to `sig` significant figures, `-` for none.
pub fn opt(v: Option<f64>, sig: usize) -> String {
    v.map(|x| crate::format::fmt_sig(x, sig))
        .unwrap_or_else(|| "-".into())
}

/// A relative error as a signed percentage.
pub fn pct(v: Option<f64>) -> String {
    v.map(|x| format!("{:+.1} %", 100.0 * x))
        .unwrap_or_else(|| "-".into())
}

/// A file written under a temporary name in the destination's directory
/// and renamed over the destination by [`AtomicFile::commit`]: readers see
/// the old file or the whole new one, never half of it, and a failure (or
/// a drop without commit) removes the temporary file. The rename is atomic
/// on POSIX file systems because both names share a directory. A symbolic
/// link is followed to its file; a character device or FIFO is written
/// through ([`super::output_guard`] says why).
pub struct AtomicFile {
    dest: PathBuf,
    /// The temporary file; `None` when writing through.
    tmp: Option<PathBuf>,
    file: Option<std::fs::File>,
}

impl AtomicFile {
    /// Opens the temporary file; an unwritable destination, or one of
    /// `inputs`, is a user error.
    pub fn create(dest: &Path, inputs: &Inputs) -> Result<AtomicFile, CliError> {
        match check_output_file(dest, inputs)? {
            Target::Replace(path) => {
                cleanup::sweep_stale_temps(&path);
                let tmp = temp_sibling(&path);
                let file = cleanup::create_temp(&tmp).map_err(|e| cannot_write(dest, &e))?;
                Ok(AtomicFile {
                    dest: path,
                    tmp: Some(tmp),
                    file: Some(file),
                })
            }
            Target::WriteThrough(path) => {
                let file = guard::open_write_through(&path).map_err(|e| cannot_write(dest, &e))?;
                Ok(AtomicFile {
                    dest: path,
                    tmp: None,
                    file: Some(file),
                })
            }
        }
    }

    pub fn writer(&mut self) -> &mut std::fs::File {
        self.file.as_mut().expect("open until commit")
    }

    /// Flushes to disk and renames over the destination.
    pub fn commit(mut self) -> Result<(), CliError> {
        let mut file = self.file.take().expect("open until commit");
        file.flush().map_err(|e| cannot_write(&self.dest, &e))?;
        let Some(tmp) = self.tmp.take() else {
            return Ok(());
        };
        let done = file
            .sync_all()
            .and_then(|()| {
                drop(file);
                std::fs::rename(&tmp, &self.dest)
            })
            .map_err(|e| cannot_write(&self.dest, &e));
        if done.is_err() {
            let _ = std::fs::remove_file(&tmp);
        }
        cleanup::forget_temp(&tmp);
        done
    }
}

impl Drop for AtomicFile {
    fn drop(&mut self) {
        self.file.take();
        if let Some(tmp) = self.tmp.take() {
            let _ = std::fs::remove_file(&tmp);
            cleanup::forget_temp(&tmp);
        }
    }
}

/// Writes `bytes` to `path` atomically (see [`AtomicFile`]).
pub fn write_atomically(path: &Path, bytes: &[u8], inputs: &Inputs) -> Result<(), CliError> {
    let mut f = AtomicFile::create(path, inputs)?;
    f.writer()
        .write_all(bytes)
        .map_err(|e| cannot_write(path, &e))?;
    f.commit()
}

/// Writes several files of one output atomically as a group as far as a
/// file system allows: every temporary file is complete before the first
/// rename, so a failure while producing or writing any of them leaves none.
pub fn write_all_atomically(files: &[(PathBuf, Vec<u8>)], inputs: &Inputs) -> Result<(), CliError> {
    let mut pending = Vec::with_capacity(files.len());
    for (path, bytes) in files {
        let mut f = AtomicFile::create(path, inputs)?;
        f.writer()
            .write_all(bytes)
            .map_err(|e| cannot_write(path, &e))?;
        pending.push(f);
    }
    pending.into_iter().try_for_each(AtomicFile::commit)
}

/// Checks, before any work, that files can be created in `dir` (creating
/// it if needed, and removing it again if the run fails), so that a long
/// computation does not end in an I/O error; that it holds none of the
/// run's inputs and no other command's output (`guard::claim_dir`).
/// Output files named beside it (`--write-log`) are checked first.
pub fn check_output_dir(dir: &Path, command: &str, inputs: &Inputs) -> Result<(), CliError> {
    if dir.exists() && !dir.is_dir() {
        return Err(CliError::input(format!(
            "output directory {}: exists and is not a directory",
            dir.display()
        )));
    }
    guard::refuse_dir_holding_input(dir, inputs)?;
    guard::claim_dir(dir, command, inputs)?;
    cleanup::create_dir_all(dir).map_err(|e| {
        CliError::input(format!(
            "output directory {}: cannot create it: {e}",
            dir.display()
        ))
    })?;
    // Again once the folder exists: only then does its path resolve
    // (`new/../D` is `D` after `new/` is made), and checked before alone
    // it hid the inputs in `D`.
    // A refusal removes the folders just made (the library's callers too).
    if let Err(e) = guard::refuse_dir_holding_input(dir, inputs) {
        cleanup::settle_output_dir(dir, false);
        return Err(e);
    }
    // A run killed outright (SIGKILL) between creating and removing its
    // probe left it: the next run into the folder sweeps it.
    cleanup::sweep_stale_temps(&dir.join("probe"));
    probe(&temp_sibling(&dir.join("probe")), dir)
}

/// The report bundle's guard ([`crate::report::Guard`]): refuses a file
/// of the bundle that is one of the command's inputs
/// (`guard::refuse_if_unnamed_input`), e.g. `--data out/tables/paper-1.csv`.
pub fn not_an_input(path: &Path, inputs: &Inputs) -> Result<(), String> {
    guard::refuse_if_unnamed_input(path, inputs).map_err(|e| e.to_string())
}

/// Checks, before any work, that `path` can be written: what kind of file
/// it names ([`guard::resolve`]), that it is no input of the command, and
/// for a regular file that its directory exists and is writable. Returns
/// how it will be written.
pub fn check_output_file(path: &Path, inputs: &Inputs) -> Result<Target, CliError> {
    let target = guard::resolve(path)?;
    guard::refuse_if_input(path, inputs)?;
    guard::declare_output_file(path);
    let Target::Replace(file) = &target else {
        // Opening a FIFO to probe it would wait for a reader.
        return Ok(target);
    };
    let parent = match file.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    if !parent.is_dir() {
        return Err(CliError::input(format!(
            "output {}: the directory {} does not exist",
            path.display(),
            parent.display()
        )));
    }
    probe(&temp_sibling(file), path)?;
    Ok(target)
}

/// Creates and removes `probe_path`, reporting failure against `shown`.
/// The probe is the temporary file's own name, so it is registered like
/// one: a SIGTERM between its creation and removal left it behind (the
/// interrupt test saw `.big.csv.tmp-PID` on a loaded machine).
fn probe(probe_path: &Path, shown: &Path) -> Result<(), CliError> {
    drop(cleanup::create_temp(probe_path).map_err(|e| cannot_write(shown, &e))?);
    let _ = std::fs::remove_file(probe_path);
    cleanup::forget_temp(probe_path);
    Ok(())
}

/// `.NAME.tmp-PID` next to `path`, within the file-name limit
/// ([`crate::atomic_file::temp_sibling`]).
fn temp_sibling(path: &Path) -> PathBuf {
    crate::atomic_file::temp_sibling(path)
}

/// Output that cannot be written is the user's to fix (path, permissions,
/// space), so it exits with 2.
fn cannot_write(path: &Path, e: &std::io::Error) -> CliError {
    CliError::input(format!("cannot write {}: {e}", path.display()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn atomic_write_replaces_whole_files_and_cleans_up() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("a.csv");
        let inputs = Inputs::new();
        write_atomically(&p, b"one", &inputs).unwrap();
        write_atomically(&p, b"two", &inputs).unwrap();
        assert_eq!(std::fs::read(&p).unwrap(), b"two");
        // A dropped, uncommitted file leaves neither the target nor a temp.
        let q = dir.path().join("b.csv");
        drop(AtomicFile::create(&q, &inputs).unwrap());
        let names: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
        assert_eq!(names.len(), 1, "only a.csv: {names:?}");
        // Unwritable destinations are user errors (exit 2).
        let e = write_atomically(&dir.path().join("no/such/dir/x"), b"", &inputs).unwrap_err();
        assert_eq!(e.exit_code(), 2);
        assert_eq!(
            check_output_dir(&p, "test", &inputs)
                .unwrap_err()
                .exit_code(),
            2
        );
    }

    #[test]
    fn csv_rows_keep_declared_order_and_plain_decimals() {
        #[derive(serde::Serialize)]
        struct R {
            id: String,
            tiny: f64,
            big: f64,
            n: usize,
            none: Option<f64>,
        }
        let rows = [R {
            id: "1e3".into(),
            tiny: 1.2e-7,
            big: 3.0e17,
            n: 4,
            none: None,
        }];
        let mut out = Vec::new();
        write_csv_rows(&rows, &mut out, &Inputs::new()).unwrap();
        let text = String::from_utf8(out).unwrap();
        assert!(text.starts_with("# swimbot "), "{text}");
        let rows: String = text
            .lines()
            .filter(|l| !l.starts_with('#'))
            .map(|l| format!("{l}\n"))
            .collect();
        assert_eq!(
            rows,
            "id,tiny,big,n,none\n1e3,0.00000012,300000000000000000,4,\n"
        );
    }
}
