//! The study's pin on every file its dataset reads besides itself (a
//! CSV's `# setup_file`): each with the SHA-256 of its bytes when the
//! study was calibrated. The dataset's own bytes are pinned in
//! `[dataset]`; a setup file edited after `init` changes every case's
//! geometry as much as an edited CSV does, so it is refused alike.

use super::error::StudyError;
use crate::provenance::Inputs;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// One pinned file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PinRecord {
    /// Relative to the study's folder when it was read by a relative path.
    pub path: PathBuf,
    pub sha256: String,
}

/// The files `inputs` recorded while the dataset at `data` was loaded,
/// other than the dataset itself, as the study stores them.
pub fn pins_of(study: &Path, data: &Path, inputs: &Inputs) -> Vec<PinRecord> {
    inputs
        .list()
        .into_iter()
        .filter(|i| !same_file(Path::new(&i.path), data))
        .map(|i| PinRecord {
            path: super::stored_path(study, Path::new(&i.path)),
            sha256: i.sha256,
        })
        .collect()
}

/// Every file read while loading the dataset (`inputs`) is pinned with
/// the same bytes, or the study is refused naming the file.
pub fn check(
    study: &Path,
    pins: &[PinRecord],
    data: &Path,
    inputs: &Inputs,
) -> Result<(), StudyError> {
    for read in inputs.list() {
        let read_path = Path::new(&read.path);
        if same_file(read_path, data) {
            continue;
        }
        let pin = pins
            .iter()
            .find(|p| same_file(&super::resolve(study, &p.path), read_path));
        let message = match pin {
            Some(p) if p.sha256 == read.sha256 => continue,
            Some(p) => format!(
                "the dataset changed since the study was calibrated: {}, which the dataset {} reads, has SHA-256 {}, not the pinned {}: its steps were calibrated on other numbers. Start the study again with `swimbot init --force --data {}`, or restore the file",
                read.path,
                data.display(),
                read.sha256,
                p.sha256,
                data.display()
            ),
            None => format!(
                "the dataset {} reads {}, which the study does not pin (no `[[dataset.pin]]` for it): a change to it would go unseen. Start the study again with `swimbot init --force --data {}`",
                data.display(),
                read.path,
                data.display()
            ),
        };
        return Err(StudyError::InputChanged {
            file: study.to_path_buf(),
            input: read_path.to_path_buf(),
            message,
        });
    }
    Ok(())
}

/// The same file by its resolved path (a path that cannot be resolved
/// only by its text).
fn same_file(a: &Path, b: &Path) -> bool {
    match (std::fs::canonicalize(a), std::fs::canonicalize(b)) {
        (Ok(x), Ok(y)) => x == y,
        _ => a == b,
    }
}
