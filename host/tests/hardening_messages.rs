//! Messages that name the file, the row or case, and the field; and the
//! inputs behind them read right: an output folder reached through a
//! missing folder, a law with a pole, `#name` without a file, CR-only line
//! ends, column names TOML cannot write bare, a robot body too short.

use crate::common::{run_in, stderr, stdout};
use std::process::Output;

const PAPER_CSV: &str = include_str!("../data/paper.csv");
const ROBOT: &str = include_str!("../data/robot.toml");

fn refused(o: &Output, needles: &[&str]) {
    let e = stderr(o);
    assert_eq!(o.status.code(), Some(2), "{e}\n{}", stdout(o));
    assert!(!e.contains("panicked"), "{e}");
    for n in needles {
        assert!(e.contains(n), "no `{n}` in: {e}");
    }
}

#[test]
fn an_output_folder_reached_through_a_missing_folder_is_checked_for_inputs() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("lab")).unwrap();
    std::fs::write(dir.path().join("lab/paper.csv"), PAPER_CSV).unwrap();
    let o = run_in(
        dir.path(),
        &["report", "--data", "lab/paper.csv", "-o", "nonexist/../lab"],
    );
    refused(&o, &["nonexist/../lab", "paper.csv"]);
    assert!(!dir.path().join("nonexist").exists());
    let left: Vec<_> = std::fs::read_dir(dir.path().join("lab")).unwrap().collect();
    assert_eq!(left.len(), 1, "{left:?}");
}

#[test]
fn a_fit_whose_law_fails_at_every_start_names_file_case_place_and_formula() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("paper.csv"), PAPER_CSV).unwrap();
    std::fs::write(
        dir.path().join("pole.toml"),
        "[[effect]]\nname = \"pole\"\nstatement = \"a law with a pole at tail-1\"\nreference = \"a test\"\n\n\
         [[effect.param]]\nname = \"k\"\nunit = \"1\"\ndefault = 1.0\nmin = 0.1\nmax = 10.0\nfree = true\ndoc = \"k\"\n\n\
         [effect.places]\n\"tail.torque\" = \"k/(tail_length_mm-130)\"\n",
    )
    .unwrap();
    let args = [
        "--data",
        "paper.csv",
        "--effect-file",
        "pole.toml",
        "--effect",
        "pole",
    ];
    let fit: Vec<&str> = ["fit"].iter().chain(&args).copied().collect();
    refused(
        &run_in(dir.path(), &fit),
        &[
            "paper.csv",
            "tail-1",
            "tail.torque",
            "k/(tail_length_mm-130)",
            "pole.toml",
        ],
    );
}

#[test]
fn add_hash_name_without_a_file_says_so() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("paper.csv"), PAPER_CSV).unwrap();
    let o = run_in(dir.path(), &["init", "--data", "paper.csv"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let o = run_in(dir.path(), &["add", "#name"]);
    refused(&o, &["#name", "no effects file before `#`"]);
    assert!(!stderr(&o).contains(", field"), "{}", stderr(&o));
}

#[test]
fn a_csv_with_cr_only_line_ends_reads_as_the_same_dataset() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("lf.csv"), PAPER_CSV).unwrap();
    std::fs::write(dir.path().join("cr.csv"), PAPER_CSV.replace('\n', "\r")).unwrap();
    let json = |name: &str| {
        let o = run_in(dir.path(), &["compare", "--data", name, "--format", "csv"]);
        assert!(o.status.success(), "{name}: {}", stderr(&o));
        stdout(&o)
            .lines()
            .filter(|l| !l.starts_with('#'))
            .collect::<Vec<_>>()
            .join("\n")
    };
    assert_eq!(json("cr.csv"), json("lf.csv"));
}

#[test]
fn convert_writes_column_names_toml_cannot_take_bare_and_reads_them_back() {
    let dir = tempfile::tempdir().unwrap();
    let mut lines: Vec<String> = PAPER_CSV.lines().map(str::to_string).collect();
    let header = lines.iter().position(|l| !l.starts_with('#')).unwrap();
    lines[header].push_str(",room temp (C),temp.c,Opérateur");
    for l in &mut lines[header + 1..] {
        if !l.is_empty() {
            l.push_str(",21.5,x,Zoë");
        }
    }
    std::fs::write(dir.path().join("extra.csv"), lines.join("\n") + "\n").unwrap();
    let o = run_in(
        dir.path(),
        &["convert", "extra.csv", "--to", "toml", "-o", "extra.toml"],
    );
    if !o.status.success() {
        // Columns outside the format may be refused; then by name.
        refused(&o, &["extra.csv"]);
        return;
    }
    let back = run_in(
        dir.path(),
        &["convert", "extra.toml", "--to", "csv", "-o", "back.csv"],
    );
    assert!(back.status.success(), "{}", stderr(&back));
    let text = std::fs::read_to_string(dir.path().join("back.csv")).unwrap();
    for name in ["room temp (C)", "temp.c", "Opérateur", "Zoë"] {
        assert!(text.contains(name), "{name} lost: {text}");
    }
}

#[test]
fn a_robot_body_shorter_than_its_diameter_names_the_file_and_field() {
    let dir = tempfile::tempdir().unwrap();
    let at = ROBOT.find("[body]").unwrap();
    let len = at + ROBOT[at..].find("length_mm = ").unwrap();
    let end = len + ROBOT[len..].find('\n').unwrap();
    let robot = format!("{}length_mm = 2{}", &ROBOT[..len], &ROBOT[end..]);
    std::fs::write(dir.path().join("short.toml"), robot).unwrap();
    let o = run_in(dir.path(), &["sim", "--robot", "short.toml", "-o", "out"]);
    refused(&o, &["short.toml", "body.length_mm"]);
    assert!(!stderr(&o).contains("case `tail-1`"), "{}", stderr(&o));
}
