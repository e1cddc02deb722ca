//! The page's bundle: beside `index.html`, every figure panel as its own
//! SVG file (`figures/`), every table as CSV and JSON (`tables/`), and
//! `manifest.json` listing each file with its kind and caption and the
//! command that wrote the folder. Read back from the rendered page, so
//! the files hold exactly what the page shows.
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

/// The text of `html` with tags removed and the page's entities decoded.
pub fn text_of(html: &str) -> String {
    let mut out = String::with_capacity(html.len());
    let mut in_tag = false;
    let html = html.replace("<br>", " ");
    for ch in html.chars() {
        match ch {
            '<' => in_tag = true,
            '>' if in_tag => in_tag = false,
            c if !in_tag => out.push(c),
            _ => {}
        }
    }
    out.replace("&lt;", "<")
        .replace("&gt;", ">")
        .replace("&quot;", "\"")
        .replace("&#39;", "'")
        .replace("&amp;", "&")
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ")
}

/// The elements `<tag ...>...</tag>` of `html` in order, without nesting.
fn elements<'a>(html: &'a str, tag: &str) -> Vec<&'a str> {
    let (open, close) = (format!("<{tag}"), format!("</{tag}>"));
    let mut out = Vec::new();
    let mut rest = html;
    while let Some(i) = rest.find(&open) {
        let Some(j) = rest[i..].find(&close) else {
            break;
        };
        out.push(&rest[i..i + j + close.len()]);
        rest = &rest[i + j + close.len()..];
    }
    out
}

fn attr<'a>(element: &'a str, name: &str) -> Option<&'a str> {
    let head = &element[..element.find('>')?];
    let key = format!("{name}=\"");
    let i = head.find(&key)? + key.len();
    Some(&head[i..i + head[i..].find('"')?])
}

/// A table's rows of cell texts, header first.
fn rows(table: &str) -> Vec<Vec<String>> {
    elements(table, "tr")
        .iter()
        .map(|tr| {
            let th = elements(tr, "th");
            let cells = if th.is_empty() {
                elements(tr, "td")
            } else {
                th
            };
            cells.iter().map(|c| text_of(c)).collect()
        })
        .collect()
}

fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// The bundle's files `(relative path, bytes)` and manifest entries.
pub fn files(page: &str) -> (Vec<(String, Vec<u8>)>, Vec<Entry>) {
    let mut files = Vec::new();
    let mut entries = vec![Entry {
        file: "index.html".into(),
        kind: "page".into(),
        caption: "the whole page".into(),
        sha256: String::new(),
    }];
    for fig in elements(page, "figure") {
        let id = attr(fig, "id").unwrap_or("figure");
        let caption = elements(fig, "figcaption")
            .first()
            .map_or(String::new(), |c| text_of(c));
        let (legends, svgs): (Vec<&str>, Vec<&str>) = elements(fig, "svg")
            .into_iter()
            .partition(|s| s.contains("class=\"legend\"") && !s.contains("class=\"frame\""));
        // The figure's one legend, drawn beside its panels, is a file of
        // its own and not a numbered panel.
        for svg in legends {
            let file = format!("figures/{id}-legend.svg");
            entries.push(Entry {
                file: file.clone(),
                kind: "figure".into(),
                caption: format!("legend of every panel. {caption}"),
                sha256: String::new(),
            });
            files.push((file, format!("{svg}\n").into_bytes()));
        }
        for (i, svg) in svgs.iter().enumerate() {
            let file = if svgs.len() == 1 {
                format!("figures/{id}.svg")
            } else {
                format!("figures/{id}-{}.svg", i + 1)
            };
            let title = svg_title(svg);
            entries.push(Entry {
                file: file.clone(),
                kind: "figure".into(),
                caption: format!("{title}: panel {} of {}. {caption}", i + 1, svgs.len()),
                sha256: String::new(),
            });
            files.push((file, format!("{svg}\n").into_bytes()));
        }
    }
    // tables are named by the section they stand in
    let mut section = "page".to_string();
    let mut title = String::new();
    let mut count = std::collections::HashMap::<String, usize>::new();
    let mut rest = page;
    loop {
        let (h2, tb) = (rest.find("<h2 id=\""), rest.find("<table"));
        match (h2, tb) {
            (Some(h), t) if t.is_none_or(|t| h < t) => {
                let el = &rest[h..];
                section = attr(el, "id").unwrap_or("page").to_string();
                title = text_of(&el[..el.find("</h2>").unwrap_or(el.len())]);
                rest = &rest[h + 4..];
            }
            (_, Some(t)) => {
                let end = rest[t..].find("</table>").map_or(rest.len(), |e| t + e + 8);
                let n = count.entry(section.clone()).or_default();
                *n += 1;
                let stem = format!("tables/{section}-{n}");
                let rows = rows(&rest[t..end]);
                let csv: String = rows
                    .iter()
                    .map(|r| r.iter().map(|c| csv_field(c)).collect::<Vec<_>>().join(",") + "\n")
                    .collect();
                let json = table_json(&rows);
                let caption = format!("table {n} of section \"{title}\"");
                for (ext, kind, bytes) in [
                    ("csv", "table-csv", csv.into_bytes()),
                    ("json", "table-json", json.into_bytes()),
                ] {
                    entries.push(Entry {
                        file: format!("{stem}.{ext}"),
                        kind: kind.into(),
                        caption: caption.clone(),
                        sha256: String::new(),
                    });
                    files.push((format!("{stem}.{ext}"), bytes));
                }
                rest = &rest[end..];
            }
            _ => break,
        }
    }
    (files, entries)
}

/// A panel's title: its text in the largest font (the first of those).
fn svg_title(svg: &str) -> String {
    let size = |t: &str| {
        attr(t, "font-size")
            .and_then(|s| s.parse::<f64>().ok())
            .unwrap_or(0.0)
    };
    let texts = elements(svg, "text");
    let best = texts.iter().fold(None::<&&str>, |b, t| match b {
        Some(b) if size(b) >= size(t) => Some(b),
        _ => Some(t),
    });
    best.map(|t| text_of(t)).unwrap_or_default()
}

/// A cell as JSON: a number when its text is one (a column of values
/// reads as numbers, not strings), else its text.
fn cell_json(text: &str) -> serde_json::Value {
    text.parse::<f64>()
        .ok()
        .filter(|v| v.is_finite())
        .and_then(serde_json::Number::from_f64)
        .map_or_else(
            || serde_json::Value::String(text.to_string()),
            serde_json::Value::Number,
        )
}

/// Rows as a JSON array of objects keyed by the header's texts.
fn table_json(rows: &[Vec<String>]) -> String {
    let Some((head, body)) = rows.split_first() else {
        return "[]".into();
    };
    let objects: Vec<serde_json::Map<String, serde_json::Value>> = body
        .iter()
        .map(|r| {
            head.iter()
                .zip(r)
                .map(|(k, v)| (k.clone(), cell_json(v)))
                .collect()
        })
        .collect();
    serde_json::to_string_pretty(&objects).expect("strings serialise") + "\n"
}

/// A file of the bundle written from the values that made it (the paper's
/// tables and equations), not read back from the page.
pub struct Written {
    /// Relative to the folder (`tables/NAME`).
    pub file: String,
    /// `table-latex`, `table-markdown`, `equations-latex`, `equations-markdown`.
    pub kind: &'static str,
    pub caption: String,
    pub text: String,
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

/// Write `page` and its bundle into `dir`, all-or-none (module docs);
/// returns the page's path. Every file it would write or remove passes
/// `guard` first, before any is touched; every file names `inputs` in its
/// provenance.
pub fn write(
    dir: &Path,
    command: &str,
    page: &str,
    written: &[Written],
    guard: Guard,
    inputs: &crate::provenance::Inputs,
) -> Result<PathBuf, BundleError> {
    check_dir(dir, command)?;
    let provenance = crate::provenance::Provenance::capture(inputs);
    let page = provenance.into_html(page);
    let (mut files, mut entries) = files(&page);
    for w in written {
        entries.push(Entry {
            file: w.file.clone(),
            kind: w.kind.into(),
            caption: w.caption.clone(),
            sha256: String::new(),
        });
        files.push((
            w.file.clone(),
            with_comments(&provenance, &w.file, &w.text).into_bytes(),
        ));
    }
    // every file of the bundle can be traced back on its own
    for (rel, bytes) in &mut files {
        if rel.ends_with(".svg") {
            *bytes = provenance
                .into_svg(&String::from_utf8_lossy(bytes))
                .into_bytes();
        } else if rel.ends_with(".csv") {
            let mut with = provenance.comment_block().into_bytes();
            with.append(bytes);
            *bytes = with;
        }
    }
    let page = page.into_bytes();
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

    const PAGE: &str = "<h2 id=\"a\">1. One</h2><table><tr><th>x, y</th><th>U (mm/s)</th></tr>\
        <tr><td>tail-1</td><td>0.2609 &plusmn; 1<br><span class=\"fall\">falls</span></td></tr></table>\
        <figure id=\"f\"><div><svg><text font-size=\"11\">8.4</text><text font-size=\"14\">(a) first</text></svg></div><div><svg><text>(b)</text></svg>\
        </div><figcaption><b>Fig.</b> Two &amp; panels.</figcaption></figure>";

    #[test]
    fn every_panel_and_table_becomes_a_file_named_in_the_manifest() {
        let (files, entries) = files(PAGE);
        let names: Vec<&str> = files.iter().map(|f| f.0.as_str()).collect();
        assert_eq!(
            names,
            [
                "figures/f-1.svg",
                "figures/f-2.svg",
                "tables/a-1.csv",
                "tables/a-1.json"
            ]
        );
        assert_eq!(entries.len(), 5, "the page and four files");
        assert!(entries[1]
            .caption
            .starts_with("(a) first: panel 1 of 2. Fig. Two & panels."));
        let csv = String::from_utf8(files[2].1.clone()).unwrap();
        assert_eq!(csv, "\"x, y\",U (mm/s)\ntail-1,0.2609 &plusmn; 1 falls\n");
        let json: serde_json::Value = serde_json::from_slice(&files[3].1).unwrap();
        assert_eq!(json[0]["U (mm/s)"], "0.2609 &plusmn; 1 falls");
        assert_eq!(entries[3].caption, "table 1 of section \"1. One\"");
    }

    #[test]
    fn a_folder_another_command_wrote_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        write(dir.path(), "report", PAGE, &[], &|_| Ok(()), &Inputs::new()).unwrap();
        assert!(check_dir(dir.path(), "report").is_ok());
        let e = check_dir(dir.path(), "compare").unwrap_err().to_string();
        assert!(e.contains("swimbot report") && e.contains("-o"), "{e}");
        let other = tempfile::tempdir().unwrap();
        std::fs::write(other.path().join("index.html"), "<p>mine</p>").unwrap();
        assert!(check_dir(other.path(), "report").is_err());
    }
}
