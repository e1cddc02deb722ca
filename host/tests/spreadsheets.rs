//! A lab's spreadsheets as they are, through the real binary: a European
//! export (`;`, decimal commas, a BOM, CRLF) gives the comparison of the
//! file it came from; a column the format does not know (the oil's
//! temperature, a date) is carried through and offered to `diagnose`; a
//! file with too many rows is refused at once; bad cells name their file,
//! row, case and field in a message of bounded length.

use crate::common::{stderr, stdout, swimbot};
use std::path::{Path, PathBuf};
use std::process::Output;

fn paper_csv() -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/paper.csv");
    std::fs::read_to_string(path).unwrap()
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

/// A cell as a spreadsheet in a decimal-comma locale writes it: numbers
/// with a comma, text as it was.
fn euro_cell(cell: &str) -> String {
    if cell.parse::<f64>().is_ok() {
        cell.replacen('.', ",", 1)
    } else {
        cell.to_string()
    }
}

/// `text` as a European spreadsheet saves it after opening it with `,` as
/// the separator: every line split at its commas into cells (a `#` line
/// too: its cells are text, left as they are), the cells written with `;`
/// (quoted where they hold a quote), rows padded to the column count, a
/// BOM in front, CRLF line ends.
fn european_export(text: &str) -> String {
    let width = text
        .lines()
        .find(|l| !l.starts_with('#'))
        .map_or(1, |l| l.split(',').count());
    let mut w = csv::WriterBuilder::new()
        .delimiter(b';')
        .flexible(true)
        .terminator(csv::Terminator::CRLF)
        .from_writer(Vec::new());
    for line in text.lines() {
        let mut cells: Vec<String> = line.split(',').map(euro_cell).collect();
        cells.resize(width.max(cells.len()), String::new());
        w.write_record(&cells).unwrap();
    }
    let body = String::from_utf8(w.into_inner().unwrap()).unwrap();
    format!("\u{feff}{body}")
}

fn ok(o: &Output) -> String {
    assert!(o.status.success(), "{}", stderr(o));
    stdout(o)
}

/// `compare --format json` without its provenance block (which names the
/// file and its hash), as text.
fn compare_json(data: &Path, extra: &[&str]) -> (String, Output) {
    let mut args = vec![
        "compare",
        "--no-report",
        "--format",
        "json",
        "--data",
        data.to_str().unwrap(),
    ];
    args.extend(extra);
    let o = swimbot(&args);
    let mut v: serde_json::Value = serde_json::from_str(&ok(&o)).unwrap();
    v.as_object_mut().unwrap().remove("swimbot");
    (serde_json::to_string_pretty(&v).unwrap(), o)
}

#[test]
fn a_european_export_compares_byte_for_byte_as_the_original() {
    let dir = tempfile::tempdir().unwrap();
    let original = write(dir.path(), "paper.csv", &paper_csv());
    let export = european_export(&paper_csv());
    assert!(
        export.contains("tail-1;15,5;2,5;130;1,05;0,586"),
        "{export}"
    );
    assert!(export.contains("\r\n") && export.contains(";;"));
    let euro = write(dir.path(), "paper-eu.csv", &export);
    let (want, _) = compare_json(&original, &[]);
    let (got, o) = compare_json(&euro, &[]);
    assert_eq!(got, want);
    // Said once, on stderr: how the file was read.
    let err = stderr(&o);
    assert_eq!(
        err.matches("`;` between cells, decimal commas").count(),
        1,
        "{err}"
    );
    // The flag agrees with the detection.
    let (flagged, _) = compare_json(&euro, &["--decimal-comma"]);
    assert_eq!(flagged, want);
}

#[test]
fn a_quoted_decimal_comma_is_a_number_and_a_mixed_file_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let paper = paper_csv();
    let header_end = paper.find("\nid,").unwrap() + 1;
    let (head, rows) = paper.split_at(header_end);
    let quoted: String = rows
        .lines()
        .map(|l| {
            let cells: Vec<String> = l
                .split(',')
                .map(|c| match euro_cell(c) {
                    e if e.contains(',') => format!("\"{e}\""),
                    e => e,
                })
                .collect();
            cells.join(",") + "\n"
        })
        .collect();
    let path = write(dir.path(), "quoted.csv", &format!("{head}{quoted}"));
    let original = write(dir.path(), "paper.csv", &paper);
    let (want, _) = compare_json(&original, &[]);
    let (got, _) = compare_json(&path, &[]);
    assert_eq!(got, want);

    // One cell with a point among commas: what was seen, and what to do.
    let mixed = format!("{head}{}", quoted.replacen("\"0,2208\"", "0.2208", 1));
    let path = write(dir.path(), "mixed.csv", &mixed);
    let o = swimbot(&["compare", "--no-report", "--data", path.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    let e = stderr(&o);
    for needle in ["mixed.csv", "`15,5`", "`0.2208`", "one way"] {
        assert!(e.contains(needle), "`{needle}` missing from: {e}");
    }
    // `--decimal-comma` on a file of points says so.
    let o = swimbot(&[
        "compare",
        "--no-report",
        "--decimal-comma",
        "--data",
        original.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("drop the flag"), "{}", stderr(&o));
}

#[test]
fn a_row_of_names_no_separator_splits_says_what_was_seen() {
    let dir = tempfile::tempdir().unwrap();
    let piped = paper_csv().replace(',', "|");
    let path = write(dir.path(), "pipes.csv", &piped);
    let o = swimbot(&["compare", "--no-report", "--data", path.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    let e = stderr(&o);
    assert!(
        e.contains("id|wavelength_mm") && e.contains("one column") && e.contains("`;`"),
        "{e}"
    );
}

/// The paper's rows with a `temperature_c` column that is exactly the
/// relative error of U (as a drift of the oil's viscosity with temperature
/// would make it), a `date` label and a robot id that reads as a number.
fn with_temperature(paper: &str) -> String {
    let dir = tempfile::tempdir().unwrap();
    let p = write(dir.path(), "paper.csv", paper);
    let (cmp, _) = compare_json(&p, &[]);
    let cmp: serde_json::Value = serde_json::from_str(&cmp).unwrap();
    let errs: Vec<f64> = cmp["cases"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c["u_rel_err"].as_f64().unwrap())
        .collect();
    let mut out = String::new();
    let mut row = 0;
    for line in paper.lines() {
        if line.starts_with('#') {
            out += line;
        } else if line.starts_with("id,") {
            out += &format!("{line},temperature_c,date,labels.robot");
        } else {
            let t = 20.0 + 10.0 * errs[row];
            out += &format!("{line},{t},2024-05-0{},{}", row + 1, row % 2);
            row += 1;
        }
        out.push('\n');
    }
    out
}

#[test]
fn a_temperature_column_is_carried_through_and_offered_to_diagnose() {
    let dir = tempfile::tempdir().unwrap();
    let path = write(dir.path(), "warm.csv", &with_temperature(&paper_csv()));
    let (cmp, o) = compare_json(&path, &[]);
    let note = stderr(&o);
    assert!(
        note.contains("recorded variables") && note.contains("temperature_c"),
        "{note}"
    );
    assert!(note.contains("labels") && note.contains("date"), "{note}");
    let cmp: serde_json::Value = serde_json::from_str(&cmp).unwrap();
    let first = &cmp["cases"][0]["recorded"];
    assert!(first["temperature_c"].is_f64(), "{first}");
    assert_eq!(first["date"], "2024-05-01");
    assert_eq!(first["robot"], "0");

    let o = swimbot(&[
        "diagnose",
        "--no-discovery",
        "--format",
        "json",
        "--data",
        path.to_str().unwrap(),
    ]);
    let d: serde_json::Value = serde_json::from_str(&ok(&o)).unwrap();
    let trends = d["trends"].as_array().unwrap();
    let top_u = trends.iter().find(|t| t["quantity"] == "u").unwrap();
    assert_eq!(top_u["feature_id"], "temperature_c", "{top_u}");
    assert!(top_u["r"].as_f64().unwrap() > 0.999, "{top_u}");
    assert!(trends.iter().all(|t| t["feature_id"] != "robot"));

    // TOML and back: the same dataset, the same comparison.
    let toml = dir.path().join("warm.toml");
    let back = dir.path().join("back.csv");
    ok(&swimbot(&[
        "convert",
        path.to_str().unwrap(),
        "-o",
        toml.to_str().unwrap(),
    ]));
    let text = std::fs::read_to_string(&toml).unwrap();
    assert!(text.contains("recorded = { temperature_c = "), "{text}");
    assert!(text.contains("labels = { "), "{text}");
    ok(&swimbot(&[
        "convert",
        toml.to_str().unwrap(),
        "-o",
        back.to_str().unwrap(),
    ]));
    for p in [&toml, &back] {
        assert_eq!(compare_json(p, &[]).0, compare_json(&path, &[]).0);
    }
}

#[test]
fn a_column_one_typo_from_a_field_is_refused_not_recorded() {
    let dir = tempfile::tempdir().unwrap();
    let path = write(
        dir.path(),
        "typo.csv",
        &paper_csv().replacen("wavelength_mm,amplitude", "wavelenght_mm,amplitude", 1),
    );
    let o = swimbot(&["compare", "--no-report", "--data", path.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("did you mean `wavelength_mm`"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn a_csv_over_the_case_limit_is_refused_while_it_is_read() {
    // 2 10^5 rows keeps the test's own file small; the refusal happens at
    // row 10001 whatever the length (timings: docs/data-format.md).
    let mut text = String::from("# wire_diameter_mm = 1.0\nid,wavelength_mm\n");
    for i in 0..200_000 {
        text += &format!("c{i},15.5\n");
    }
    let dir = tempfile::tempdir().unwrap();
    let path = write(dir.path(), "big.csv", &text);
    let o = swimbot(&["compare", "--no-report", "--data", path.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    let e = stderr(&o);
    assert!(
        e.contains("big.csv: row 10003") && e.contains("at most 10000"),
        "{e}"
    );
}

#[test]
fn bad_cells_name_file_row_case_and_field_in_few_words() {
    let dir = tempfile::tempdir().unwrap();
    // An enum cell.
    let paper = paper_csv();
    let lefty = paper
        .replacen("id,wavelength_mm", "id,handedness,wavelength_mm", 1)
        .replacen("tail-1,", "tail-1,right,", 1)
        .replacen("tail-2,", "tail-2,lefty,", 1)
        .replace("\ntail-3,", "\ntail-3,,")
        .replace("\ntail-4,", "\ntail-4,,")
        .replace("\ntail-5,", "\ntail-5,,")
        .replace("\ntail-6,", "\ntail-6,,");
    let path = write(dir.path(), "lefty.csv", &lefty);
    let e = swimbot::data::load_file(&path).unwrap_err().to_string();
    let row = lefty.lines().position(|l| l.starts_with("tail-2")).unwrap() + 1;
    for needle in [
        format!("lefty.csv: row {row}"),
        "case `tail-2`".into(),
        "field `handedness`".into(),
        "lefty".into(),
    ] {
        assert!(e.contains(&needle), "`{needle}` missing from: {e}");
    }

    // 800 trial rows of one case, one bad: the field and the reason stay.
    let mut trials = String::from(
        "# wire_diameter_mm = 1.0\n# channel_diameter_mm = 35\n# channel_length_mm = 350\n# viscosity_pa_s = 3.5\n# density_kg_m3 = 985\n# body_diameter_mm = 20\n# body_length_mm = 50\n# wavelength_mm = 15\n# amplitude_mm = 2.5\n# tail_length_mm = 130\n# frequency_hz = 1\nid,u_mm_s,omega_body_hz\n",
    );
    for i in 0..800 {
        trials += &format!(
            "a,{},{}\n",
            0.5 + 1e-3 * f64::from(i % 7),
            if i == 0 { "inf" } else { "0.1" }
        );
    }
    let path = write(dir.path(), "trials.csv", &trials);
    let e = swimbot::data::load_file(&path).unwrap_err().to_string();
    assert!(e.contains("rows 13-812"), "{e}");
    assert!(
        e.contains("omega_body_trials_hz") && e.contains("non-finite"),
        "{e}"
    );
    assert!(e.len() < 300, "{} characters: {e}", e.len());

    // A long cell is echoed at most ~120 characters.
    let long = format!("\"[[{}\"", "10.0, 20.0], [".repeat(100));
    let bad = paper
        .replacen("id,wavelength_mm", "id,body_profile,wavelength_mm", 1)
        .replacen("tail-1,", &format!("tail-1,{long},"), 1)
        .replace("\ntail-2,", "\ntail-2,,")
        .replace("\ntail-3,", "\ntail-3,,")
        .replace("\ntail-4,", "\ntail-4,,")
        .replace("\ntail-5,", "\ntail-5,,")
        .replace("\ntail-6,", "\ntail-6,,");
    let path = write(dir.path(), "long.csv", &bad);
    let e = swimbot::data::load_file(&path).unwrap_err().to_string();
    assert!(
        e.contains("body_profile") && e.contains("characters in all"),
        "{e}"
    );
    assert!(e.len() < 400, "{} characters: {e}", e.len());
}

/// The paper's CSV with `;` between cells and decimal commas, and `edit`
/// applied to each data row's cells (`id` first).
fn euro_rows(edit: impl Fn(&mut Vec<String>)) -> String {
    let mut out = String::new();
    for line in paper_csv().lines() {
        if line.starts_with('#') {
            out += line;
        } else {
            let mut cells: Vec<String> = line.split(',').map(euro_cell).collect();
            edit(&mut cells);
            out += &cells.join(";");
        }
        out += "\r\n";
    }
    out
}

#[test]
fn a_sheets_padding_sep_line_and_grouped_thousands_read_as_the_original() {
    let dir = tempfile::tempdir().unwrap();
    let original = write(dir.path(), "paper.csv", &paper_csv());
    let (want, _) = compare_json(&original, &[]);
    let cases: Vec<(&str, String)> = vec![
        // Excel pads every row with the separator of an empty column.
        ("padded.csv", euro_rows(|c| c.push(String::new()))),
        // ...and writes (and reads) a `sep=;` first line.
        ("sep-line.csv", format!("sep=;\r\n{}", euro_rows(|_| ()))),
        // Thousands grouped: a point under decimal commas, a (no-break)
        // space in either mark. 0,586 written as 0,586 000 would be wrong:
        // only the integer part is grouped.
        (
            "grouped.csv",
            euro_rows(|c| {
                if c[0] == "tail-1" {
                    // 130 mm written in micrometres would be 130.000,0: use
                    // a recorded column instead, and the speed as it is.
                    c.push("1.013,25".into());
                } else if c[0] != "id" {
                    c.push("1\u{a0}013,25".into());
                } else {
                    c.push("pressure_hpa".into());
                }
            }),
        ),
    ];
    for (name, text) in cases {
        let path = write(dir.path(), name, &text);
        let (got, o) = compare_json(&path, &[]);
        let strip = |s: &str| -> serde_json::Value {
            let mut v: serde_json::Value = serde_json::from_str(s).unwrap();
            for c in v["cases"].as_array_mut().unwrap() {
                c.as_object_mut().unwrap().remove("recorded");
            }
            v
        };
        assert_eq!(strip(&got), strip(&want), "{name}: {}", stderr(&o));
        if name == "grouped.csv" {
            let v: serde_json::Value = serde_json::from_str(&got).unwrap();
            for c in v["cases"].as_array().unwrap() {
                assert_eq!(c["recorded"]["pressure_hpa"], 1013.25, "{c}");
            }
        }
    }
    // A column with no name but with cells is data nobody named: refused.
    let path = write(
        dir.path(),
        "unnamed.csv",
        &euro_rows(|c| {
            c.push(if c[0] == "tail-3" {
                "7".into()
            } else {
                String::new()
            })
        }),
    );
    let o = swimbot(&["compare", "--no-report", "--data", path.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("unnamed.csv: row ")
            && stderr(&o).contains("has no name in the header row but holds `7`"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn short_column_names_of_a_lab_are_recorded_and_a_million_names_are_read_at_once() {
    let dir = tempfile::tempdir().unwrap();
    // `T`, `pH` and `Re` are two edits from `id` but nobody's typo of it.
    let mut text = String::new();
    for line in paper_csv().lines() {
        text += line;
        if !line.starts_with('#') {
            text += if line.starts_with("id,") {
                ",T,pH,Re"
            } else {
                ",21.5,7,0.01"
            };
        }
        text += "\n";
    }
    let path = write(dir.path(), "short.csv", &text);
    let (got, o) = compare_json(&path, &[]);
    assert!(got.contains("\"pH\": 7.0"), "{got}");
    assert!(stderr(&o).contains("T, pH, Re"), "{}", stderr(&o));
    // A header row of 10^6 names (each was checked against every field's
    // for typos, and against every name before it: no answer in a minute)
    // is refused at once; 10^4 are read, a repeat among them named.
    for (count, needle) in [
        (1_000_000, "1000002 columns; at most 10000 are read"),
        (9_000, "column `x7`: the column is given twice"),
    ] {
        let mut wide = String::from("# wire_diameter_mm = 1.0\nid,wavelength_mm");
        for i in 0..count {
            wide += &format!(",x{i}");
        }
        wide += if count > 10_000 { "\n" } else { ",x7\n" };
        let path = write(dir.path(), "wide.csv", &wide);
        let start = std::time::Instant::now();
        let o = swimbot(&["compare", "--no-report", "--data", path.to_str().unwrap()]);
        assert_eq!(o.status.code(), Some(2));
        assert!(stderr(&o).contains(needle), "{}", stderr(&o));
        assert!(
            start.elapsed().as_secs_f64() < 20.0,
            "{:?}",
            start.elapsed()
        );
    }
}
