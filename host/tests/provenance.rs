//! The inputs an output names are the files its own call read: two calls
//! of the library in one process (as a notebook makes them) each record
//! what they read in an `Inputs` of their own, and the second call's
//! report does not name the first call's files.

use std::path::{Path, PathBuf};
use swimbot::data::{read_file, Dataset, ReadOptions};
use swimbot::effects::Catalogue;
use swimbot::provenance::{sha256_hex, Inputs};

fn copy_in(dir: &Path, from: &str, name: &str) -> PathBuf {
    let bytes = std::fs::read(Path::new(env!("CARGO_MANIFEST_DIR")).join(from)).unwrap();
    let to = dir.join(name);
    std::fs::write(&to, bytes).unwrap();
    to
}

/// The `(path, sha256)` pairs the report's manifest names as its inputs.
fn report_inputs(dir: &Path, data: &Dataset, inputs: &Inputs) -> Vec<(String, String)> {
    let model = swimbot::model::Model::base();
    let path = swimbot::workbench::path::user_path(&model, 0, data).unwrap();
    let page = swimbot::report::write_report(dir, &path, data, None, &|_| Ok(()), inputs).unwrap();
    let manifest = std::fs::read_to_string(page.with_file_name("manifest.json")).unwrap();
    let manifest: serde_json::Value = serde_json::from_str(&manifest).unwrap();
    manifest["swimbot"]["inputs"]
        .as_array()
        .expect("an inputs list")
        .iter()
        .map(|i| {
            let s = |k: &str| i[k].as_str().unwrap_or_default().to_string();
            (s("path"), s("sha256"))
        })
        .collect()
}

fn named(path: &Path) -> (String, String) {
    (
        path.display().to_string(),
        sha256_hex(&std::fs::read(path).unwrap()),
    )
}

#[test]
fn two_reports_in_one_process_each_name_only_the_data_they_read() {
    let dir = tempfile::tempdir().unwrap();
    let a = copy_in(dir.path(), "data/paper.csv", "a.csv");
    let b = copy_in(dir.path(), "data/paper.toml", "b.toml");
    let options = ReadOptions::default();

    let first = Inputs::new();
    let data_a = read_file(&a, &options, &first).unwrap().dataset;
    let listed_a = report_inputs(&dir.path().join("report-a"), &data_a, &first);
    assert_eq!(listed_a, vec![named(&a)]);

    let second = Inputs::new();
    let data_b = read_file(&b, &options, &second).unwrap().dataset;
    let listed_b = report_inputs(&dir.path().join("report-b"), &data_b, &second);
    assert_eq!(listed_b, vec![named(&b)], "the first call's a.csv leaked");
    // The first call's record is its own still.
    assert_eq!(first.list().len(), 1);
}

#[test]
fn an_effects_file_is_an_input_of_every_call_that_loads_it() {
    // Registered once per catalogue; recorded by each call all the same.
    let fixture = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/restated.toml");
    let (first, second) = (Inputs::new(), Inputs::new());
    let mut catalogue = Catalogue::builtin();
    let files = std::slice::from_ref(&fixture);
    catalogue.load_effect_files(files, &first).unwrap();
    catalogue.load_effect_files(files, &second).unwrap();
    for inputs in [&first, &second] {
        let listed: Vec<(String, String)> = inputs
            .list()
            .into_iter()
            .map(|i| (i.path, i.sha256))
            .collect();
        assert_eq!(listed, vec![named(&fixture)]);
    }
}
