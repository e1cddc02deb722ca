//! Provenance of an output: which swimbot made it (version and the git
//! commit it was built from, when the build knew it), the full command
//! line, every input file's path and SHA-256, and the date (UTC).
//!
//! Input files are recorded where they are read ([`Inputs::record`]: the
//! dataset, a CSV's setup file, effect files, a robot file), so that no
//! command can forget one. The record is a value, [`Inputs`], that a
//! command (or one call of the library) creates and hands to what reads
//! and to what writes: an output lists what its own command read, never
//! what an earlier call in the same process left behind (the Python
//! package calls the library many times in one interpreter).
//! [`Provenance::capture`] takes it. JSON outputs carry it as a top-level `swimbot` object,
//! CSV and TOML outputs as `#` comment lines above their content, the
//! report page as its last paragraph.
//!
//! References: FIPS 180-4, *Secure Hash Standard* (SHA-256, via the `sha2`
//! crate); RFC 3339 for the date (via `humantime`).

use serde::Serialize;
use sha2::{Digest, Sha256};
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// The git commit of the build (`host/build.rs`), `None` outside a checkout.
pub const GIT_COMMIT: Option<&str> = option_env!("SWIMBOT_GIT_COMMIT");

/// One input file: its path as given and the SHA-256 of its bytes.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct Input {
    pub path: String,
    pub sha256: String,
}

/// Everything an output records about how it was made.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct Provenance {
    pub version: String,
    /// The commit swimbot was built from (`-dirty`: with uncommitted
    /// changes), or `unknown`.
    pub commit: String,
    /// The command line, one argument per entry.
    pub command: Vec<String>,
    pub inputs: Vec<Input>,
    /// When the output was made, RFC 3339, UTC, to the second.
    pub date_utc: String,
}

/// The record of one command, or one call of the library: its command
/// line (a value the caller gives, never the process's argv: the Python
/// package runs in an interpreter whose argv names no swimbot command),
/// the files it has read (each path once, with the SHA-256 of its latest
/// bytes, in the order first read) and the output folders it claims, to
/// be marked as its own when it succeeds. Shared by reference (`&Inputs`)
/// between what reads and what writes; the locks let readers on other
/// threads (rayon, a Python call without the GIL) record too.
#[derive(Debug, Default)]
pub struct Inputs {
    command: Vec<String>,
    read: Mutex<Vec<Input>>,
    claims: Mutex<Vec<(PathBuf, String)>>,
}

impl Inputs {
    /// An empty record with no command line, for one call of the library.
    pub fn new() -> Inputs {
        Inputs::default()
    }

    /// An empty record for the command line `command`, one argument per
    /// entry (the program's name first).
    pub fn for_command(command: Vec<String>) -> Inputs {
        Inputs {
            command,
            ..Inputs::default()
        }
    }

    /// This record with the command line `command` in place of its own.
    pub fn with_command(mut self, command: Vec<String>) -> Inputs {
        self.command = command;
        self
    }

    /// The command line, one argument per entry.
    pub fn command(&self) -> &[String] {
        &self.command
    }

    /// Registers `dir` as an output folder of `command`, to be marked
    /// when the run succeeds ([`Inputs::take_claims`]).
    pub fn claim(&self, dir: &Path, command: &str) {
        let mut claims = self.claims.lock().unwrap_or_else(|e| e.into_inner());
        claims.push((dir.to_path_buf(), command.to_string()));
    }

    /// The folders claimed so far, each with its command; the list is
    /// then empty.
    pub fn take_claims(&self) -> Vec<(PathBuf, String)> {
        std::mem::take(&mut *self.claims.lock().unwrap_or_else(|e| e.into_inner()))
    }

    /// Records that `path` was read with these bytes (once per path).
    pub fn record(&self, path: &Path, bytes: &[u8]) {
        self.record_named(&path.display().to_string(), bytes);
    }

    /// Records a built-in input (the paper's data) under a descriptive name.
    pub fn record_named(&self, name: &str, bytes: &[u8]) {
        self.put(Input {
            path: name.to_string(),
            sha256: sha256_hex(bytes),
        });
    }

    /// Records every input of `other` (a study's files, for the command
    /// that works on the study).
    pub fn record_all(&self, other: &Inputs) {
        other.list().into_iter().for_each(|i| self.put(i));
    }

    /// A path read again replaces its hash in place: the list keeps the
    /// order in which files were first read.
    fn put(&self, input: Input) {
        let mut inputs = self.read.lock().unwrap_or_else(|e| e.into_inner());
        match inputs.iter_mut().find(|i| i.path == input.path) {
            Some(known) => *known = input,
            None => inputs.push(input),
        }
    }

    /// What was read so far, in the order first read.
    pub fn list(&self) -> Vec<Input> {
        self.read.lock().unwrap_or_else(|e| e.into_inner()).clone()
    }
}

impl Clone for Inputs {
    fn clone(&self) -> Inputs {
        Inputs {
            command: self.command.clone(),
            read: Mutex::new(self.list()),
            claims: Mutex::new(
                self.claims
                    .lock()
                    .unwrap_or_else(|e| e.into_inner())
                    .clone(),
            ),
        }
    }
}

/// Hex SHA-256 of `bytes`.
pub fn sha256_hex(bytes: &[u8]) -> String {
    Sha256::digest(bytes)
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

impl Provenance {
    /// The provenance of an output made now: the command line and the
    /// inputs its command has read so far, both from `inputs`.
    pub fn capture(inputs: &Inputs) -> Provenance {
        Provenance {
            version: env!("CARGO_PKG_VERSION").to_string(),
            commit: GIT_COMMIT.unwrap_or("unknown").to_string(),
            command: inputs.command().to_vec(),
            inputs: inputs.list(),
            date_utc: humantime::format_rfc3339_seconds(std::time::SystemTime::now()).to_string(),
        }
    }

    /// The command line as one could paste it into a POSIX shell.
    pub fn command_line(&self) -> String {
        self.command
            .iter()
            .map(|a| shell_quoted(a))
            .collect::<Vec<_>>()
            .join(" ")
    }

    /// Plain-text lines: `swimbot VERSION (commit C), DATE`, the command,
    /// one line per input.
    pub fn lines(&self) -> Vec<String> {
        let mut out = vec![
            format!(
                "swimbot {} (commit {}), {}",
                self.version, self.commit, self.date_utc
            ),
            format!("command: {}", self.command_line()),
        ];
        out.extend(
            self.inputs
                .iter()
                .map(|i| format!("input: {} sha256 {}", i.path, i.sha256)),
        );
        out
    }

    /// The lines as `# ` comments, for CSV and TOML files. None of them
    /// reads as a `# key = value` header line of a CSV dataset.
    pub fn comment_block(&self) -> String {
        self.lines().iter().map(|l| format!("# {l}\n")).collect()
    }
}

impl Provenance {
    /// The lines as an HTML section (the report page's last), escaped by
    /// construction as the rest of the page is (`crate::report`).
    pub fn html_section(&self) -> String {
        let section = maud::html! {
            section.provenance {
                h2 id="provenance" { "Provenance" }
                pre { (self.lines().join("\n")) }
            }
        };
        section.into_string() + "\n"
    }

    /// `page` with [`Provenance::html_section`] before `</body>` (or at the end).
    pub fn into_html(&self, page: &str) -> String {
        let at = page.rfind("</body>").unwrap_or(page.len());
        format!("{}{}{}", &page[..at], self.html_section(), &page[at..])
    }

    /// `svg` with the lines in a `<metadata>` element right after the
    /// opening `<svg ...>` tag (an XML comment could not hold the `--` of
    /// a command line).
    pub fn into_svg(&self, svg: &str) -> String {
        let at = svg
            .find("<svg")
            .and_then(|s| svg[s..].find('>').map(|e| s + e + 1))
            .unwrap_or(0);
        format!(
            "{}\n<metadata>{}</metadata>{}",
            &svg[..at],
            escape_xml(&self.lines().join("\n")),
            &svg[at..]
        )
    }
}

/// Text content of the SVG `<metadata>` element.
fn escape_xml(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// Single quotes around an argument a shell would split or expand.
fn shell_quoted(a: &str) -> String {
    let plain = !a.is_empty()
        && a.chars()
            .all(|c| c.is_ascii_alphanumeric() || "-_./:=,+@%".contains(c));
    if plain {
        a.to_string()
    } else {
        format!("'{}'", a.replace('\'', r"'\''"))
    }
}

/// A JSON object output with the provenance first, as the `swimbot` key,
/// and the value's own keys after it, in their order.
#[derive(Serialize)]
pub struct WithProvenance<'a, T: Serialize> {
    pub swimbot: Provenance,
    #[serde(flatten)]
    pub value: &'a T,
}

/// `value` with this run's provenance (see [`WithProvenance`]); `value`
/// must serialise as a JSON object (a struct or a map).
pub fn with_provenance<'a, T: Serialize>(value: &'a T, inputs: &Inputs) -> WithProvenance<'a, T> {
    WithProvenance {
        swimbot: Provenance::capture(inputs),
        value,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sha256_matches_the_standard_test_vector() {
        // FIPS 180-2, appendix B.1: "abc".
        assert_eq!(
            sha256_hex(b"abc"),
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"
        );
    }

    #[test]
    fn arguments_are_quoted_only_when_a_shell_needs_it() {
        assert_eq!(shell_quoted("--data"), "--data");
        assert_eq!(shell_quoted("a b"), "'a b'");
        assert_eq!(shell_quoted("it's"), r"'it'\''s'");
        assert_eq!(shell_quoted(""), "''");
    }

    #[test]
    fn a_recorded_input_is_captured_and_rerecorded_on_change() {
        let p = Path::new("/nonexistent/provenance-test-input.toml");
        let inputs = Inputs::new();
        inputs.record(p, b"one");
        inputs.record(p, b"two");
        let mine: Vec<Input> = Provenance::capture(&inputs)
            .inputs
            .into_iter()
            .filter(|i| i.path == p.display().to_string())
            .collect();
        assert_eq!(mine.len(), 1);
        assert_eq!(mine[0].sha256, sha256_hex(b"two"));
        let date = Provenance::capture(&inputs).date_utc;
        assert!(date.ends_with('Z') && date.len() == 20, "{date}");
    }

    #[test]
    fn html_and_svg_carry_the_lines_escaped_in_place() {
        let p = Provenance {
            version: "1.2.3".into(),
            commit: "abc".into(),
            command: vec!["swimbot".into(), "--data".into(), "<a&b>.csv".into()],
            inputs: vec![],
            date_utc: "2026-01-01T00:00:00Z".into(),
        };
        let page = p.into_html("<html><body><p>x</p></body></html>");
        assert!(page.ends_with("</pre></section>\n</body></html>"), "{page}");
        assert!(page.contains("&lt;a&amp;b&gt;.csv"), "{page}");
        let svg = p.into_svg("<?xml version=\"1.0\"?>\n<svg width=\"1\"><g/></svg>");
        assert!(
            svg.contains("<svg width=\"1\">\n<metadata>swimbot 1.2.3 (commit abc)"),
            "{svg}"
        );
        assert!(svg.ends_with("</metadata><g/></svg>"), "{svg}");
    }
}
