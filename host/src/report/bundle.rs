//! The page's bundle: beside `index.html`, every figure panel as its own
//! SVG file (`figures/`), every table as CSV and JSON (`tables/`), and
//! `manifest.json` listing each file with its kind and caption and the
//! command that wrote the folder. The files are the page's artefacts,
//! named and made by the page's builder ([`super::page::Page`]) from the
//! same values it put on the page; the bundle writes them.
//!
//! The folder is replaced all-or-none ([`crate::atomic_dir`]): an
//! interrupted run or a full disk leaves the old bundle or the new one,
//! never a page beside another run's figures. The manifest records each
//! file's SHA-256, so a reader can check that what it holds is what this
//! run wrote.
//!
//! A folder whose manifest names another command (or that holds an
//! `index.html` without a manifest) is refused: no command silently
//! overwrites another command's page.

use super::page::{Artefact, Page};
use serde::Serialize;
use std::path::{Path, PathBuf};

/// One file of the bundle, as the manifest lists it.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct Entry {
    /// Relative to the folder.
    pub file: String,
    /// `page`, `figure` (SVG), `table-csv` or `table-json`.
    pub kind: String,
    pub caption: String,
    /// Hex SHA-256 of the file as written (empty until the bytes are final).
    pub sha256: String,
}

#[derive(Debug, Serialize)]
struct Manifest<'a> {
    command: &'a str,
    swimbot_version: &'a str,
    files: &'a [Entry],
}

/// Refuse `dir` when another command's page is in it.
pub fn check_dir(dir: &Path, command: &str) -> Result<(), BundleError> {
    let manifest = dir.join("manifest.json");
    match read_manifest(&manifest) {
        Ok(text) => {
            let written_by = serde_json::from_str::<serde_json::Value>(&text)
                .ok()
                .and_then(|v| v.get("command")?.as_str().map(str::to_string));
            match written_by {
                Some(c) if c == command => Ok(()),
                Some(other) => Err(BundleError::OtherCommand {
                    dir: dir.to_path_buf(),
                    other,
                    command: command.to_string(),
                }),
                None => Err(BundleError::NotOurManifest { manifest }),
            }
        }
        Err(_) if dir.join("index.html").exists() => Err(BundleError::ForeignPage {
            dir: dir.to_path_buf(),
            command: command.to_string(),
        }),
        Err(_) => Ok(()),
    }
}

/// Why a page's bundle was not written: the folder and the command as
/// data. The folder is as it was.
#[derive(Debug, thiserror::Error)]
pub enum BundleError {
    /// `dir` holds the page that command `other` wrote.
    #[error(
        "output directory {}: holds the page `swimbot {other}` wrote; give this `swimbot {command}` another folder with -o, or remove that one",
        .dir.display()
    )]
    OtherCommand {
        dir: PathBuf,
        other: String,
        command: String,
    },
    #[error("{}: not a manifest swimbot wrote; give another folder with -o", .manifest.display())]
    NotOurManifest { manifest: PathBuf },
    /// `dir` holds an `index.html` without a manifest of ours.
    #[error(
        "output directory {}: holds an index.html that no `swimbot {command}` wrote; give another folder with -o, or remove it",
        .dir.display()
    )]
    ForeignPage { dir: PathBuf, command: String },
    /// A file of the bundle the command's [`Guard`] refused, in its words.
    #[error("{0}")]
    Refused(String),
    /// Writing `path` (the folder, or a file in it) failed.
    #[error("{}: {error} (the folder is as it was)", .path.display())]
    Write {
        path: PathBuf,
        error: std::io::Error,
    },
    /// The page's model could not predict a case.
    #[error("{0}")]
    Model(#[from] crate::model::ModelError),
}

/// A manifest read back, bounded ([`crate::input_file`]).
fn read_manifest(path: &Path) -> Result<String, crate::input_file::ReadError> {
    crate::input_file::read_text(path, crate::input_file::cap::MANIFEST, "a manifest")
}

/// An artefact's text with the provenance in it, as its format holds it:
/// in an SVG's `<metadata>`, as `#` lines on top of a CSV, as comments of
/// LaTeX and Markdown; a JSON file has no comment and none is added.
fn traced(prov: &crate::provenance::Provenance, a: &Artefact) -> String {
    if a.file.ends_with(".svg") {
        prov.into_svg(&a.text)
    } else if a.file.ends_with(".csv") {
        prov.comment_block() + &a.text
    } else if a.file.ends_with(".tex") || a.file.ends_with(".md") {
        with_comments(prov, &a.file, &a.text)
    } else {
        a.text.clone()
    }
}

/// `text` with the provenance's lines on top as comments of its format:
/// `%` for LaTeX, an HTML comment for Markdown. Each line is kept to one
/// line, and a Markdown comment cannot be closed early by a path holding
/// `-->`.
fn with_comments(prov: &crate::provenance::Provenance, file: &str, text: &str) -> String {
    let lines: Vec<String> = prov
        .comment_block()
        .lines()
        .map(|l| {
            l.trim_start_matches("# ")
                .chars()
                .map(|c| if c.is_control() { ' ' } else { c })
                .collect()
        })
        .collect();
    let head: String = if file.ends_with(".tex") {
        lines.iter().map(|l| format!("% {l}\n")).collect()
    } else {
        let body: Vec<String> = lines.iter().map(|l| l.replace("--", "- -")).collect();
        format!("<!--\n{}\n-->\n\n", body.join("\n"))
    };
    head + text
}

/// What may not be written or removed: `guard` refuses a path (the CLI's
/// check that an output is none of the command's input files).
pub type Guard<'a> = &'a dyn Fn(&Path) -> Result<(), String>;

/// Write `page` and its artefacts into `dir`, all-or-none (module docs);
/// returns the page's path. Every file it would write or remove passes
/// `guard` first, before any is touched; every file names `inputs` in its
/// provenance.
pub fn write(
    dir: &Path,
    command: &str,
    page: &Page,
    guard: Guard,
    inputs: &crate::provenance::Inputs,
) -> Result<PathBuf, BundleError> {
    check_dir(dir, command)?;
    let provenance = crate::provenance::Provenance::capture(inputs);
    let mut entries = vec![Entry {
        file: "index.html".into(),
        kind: "page".into(),
        caption: "the whole page".into(),
        sha256: String::new(),
    }];
    let mut files = Vec::new();
    for a in &page.artefacts {
        entries.push(Entry {
            file: a.file.clone(),
            kind: a.kind.into(),
            caption: a.caption.clone(),
            sha256: String::new(),
        });
        // every file of the bundle can be traced back on its own
        files.push((a.file.clone(), traced(&provenance, a).into_bytes()));
    }
    let page = provenance.into_html(&page.html).into_bytes();
    for e in &mut entries {
        let bytes = files.iter().find(|f| f.0 == e.file).map_or(&page, |f| &f.1);
        e.sha256 = crate::provenance::sha256_hex(bytes);
    }
    let manifest = Manifest {
        command,
        swimbot_version: env!("CARGO_PKG_VERSION"),
        files: &entries,
    };
    let manifest = crate::provenance::with_provenance(&manifest, inputs);
    files.push((
        "manifest.json".into(),
        (serde_json::to_string_pretty(&manifest).expect("serialisable") + "\n").into_bytes(),
    ));
    files.push(("index.html".into(), page));
    // a page rewritten with fewer figures leaves no stale ones behind; only
    // the files the previous run's manifest lists go (removing the whole
    // folders deleted whatever else a user had put in them)
    let previous = previous_files(dir);
    for rel in previous.iter().chain(files.iter().map(|f| &f.0)) {
        guard(&dir.join(rel)).map_err(BundleError::Refused)?;
    }
    let replaced: std::collections::HashSet<PathBuf> = previous
        .iter()
        .chain(files.iter().map(|f| &f.0))
        .map(PathBuf::from)
        .collect();
    let say = |error| BundleError::Write {
        path: dir.to_path_buf(),
        error,
    };
    let staging =
        crate::atomic_dir::Staging::begin(dir, &|rel| replaced.contains(rel)).map_err(say)?;
    for (rel, bytes) in &files {
        staging
            .write(rel, bytes)
            .map_err(|error| BundleError::Write {
                path: dir.join(rel),
                error,
            })?;
    }
    staging.commit().map_err(say)?;
    Ok(dir.join("index.html"))
}

/// The figures and tables an earlier run's `manifest.json` in `dir` lists,
/// as `figures/NAME` or `tables/NAME` (anything else a manifest may say,
/// such as `../x`, is not ours to remove).
fn previous_files(dir: &Path) -> Vec<String> {
    let Ok(text) = read_manifest(&dir.join("manifest.json")) else {
        return Vec::new();
    };
    let Ok(v) = serde_json::from_str::<serde_json::Value>(&text) else {
        return Vec::new();
    };
    let files = v.get("files").and_then(|f| f.as_array());
    files
        .into_iter()
        .flatten()
        .filter_map(|e| e.get("file")?.as_str())
        .filter(|rel| {
            rel.split_once('/').is_some_and(|(sub, name)| {
                ["figures", "tables"].contains(&sub)
                    && !name.is_empty()
                    && !name.contains('/')
                    && !name.contains('\\')
                    && !name.starts_with('.')
            })
        })
        .map(str::to_string)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::provenance::Inputs;

    fn page() -> Page {
        let body = super::super::page::tests::sample();
        Page::new(format!("<body>{}</body>", body.html()), body)
    }

    #[test]
    fn every_artefact_is_written_and_named_in_the_manifest() {
        let dir = tempfile::tempdir().unwrap();
        write(dir.path(), "report", &page(), &|_| Ok(()), &Inputs::new()).unwrap();
        let manifest: serde_json::Value = serde_json::from_str(
            &std::fs::read_to_string(dir.path().join("manifest.json")).unwrap(),
        )
        .unwrap();
        let files: Vec<&str> = manifest["files"]
            .as_array()
            .unwrap()
            .iter()
            .map(|f| f["file"].as_str().unwrap())
            .collect();
        assert_eq!(
            files,
            [
                "index.html",
                "figures/f-1.svg",
                "figures/f-2.svg",
                "tables/a-1.csv",
                "tables/a-1.json"
            ]
        );
        for f in &files[1..] {
            assert!(dir.path().join(f).is_file(), "{f}");
        }
        let csv = std::fs::read_to_string(dir.path().join("tables/a-1.csv")).unwrap();
        assert!(csv.starts_with('#') && csv.ends_with("tail-1,0.2609 &plusmn; 1 falls\n"));
        let svg = std::fs::read_to_string(dir.path().join("figures/f-1.svg")).unwrap();
        assert!(svg.contains("<metadata>"), "{svg}");
    }

    #[test]
    fn a_folder_another_command_wrote_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        write(dir.path(), "report", &page(), &|_| Ok(()), &Inputs::new()).unwrap();
        assert!(check_dir(dir.path(), "report").is_ok());
        let e = check_dir(dir.path(), "compare").unwrap_err().to_string();
        assert!(e.contains("swimbot report") && e.contains("-o"), "{e}");
        let other = tempfile::tempdir().unwrap();
        std::fs::write(other.path().join("index.html"), "<p>mine</p>").unwrap();
        assert!(check_dir(other.path(), "report").is_err());
    }
}
