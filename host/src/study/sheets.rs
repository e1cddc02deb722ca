//! Run sheets joined to the study's data: the runs a lab made after the
//! study began (the sheet `swimbot plan` wrote, filled in; or the cases
//! `swimbot log` made from run logs), each pinned by its SHA-256 beside
//! the dataset, with the ids of the rows it brought.
//!
//! The dataset file is never rewritten: the study's data are the pinned
//! dataset followed by each pinned sheet's rows, in the order they joined,
//! so which rows came from which sheet is in the file and every one of
//! them is checked on open as the dataset is. Joining a sheet
//! recalibrates every step on the joined data (each step's effect
//! calibrated again on top of the steps before it, as `add` calibrated
//! it) and diagnoses the model again: one new study, written at once, or
//! nothing.

use super::data_add::{merge, Merged, SheetError};
use super::diagnosis::DiagnosisRecord;
use super::error::StudyError;
use super::snapshot::{Snapshot, Stats};
use super::{now_utc, resolve, stored_path, AddOptions, Study};
use crate::data::Dataset;
use crate::provenance::{sha256_hex, Inputs};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// One joined sheet, as the study stores it (`[[dataset.sheet]]`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SheetRecord {
    /// Relative to the study's folder when it was given relative.
    pub path: PathBuf,
    /// SHA-256 of its bytes: a changed sheet is refused, as a changed dataset is.
    pub sha256: String,
    /// The ids of the rows that joined, in order.
    pub cases: Vec<String>,
    /// Rows without any measurement (runs not made), left out.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub skipped: Vec<String>,
    /// When it joined, RFC 3339 UTC.
    pub joined_utc: String,
}

/// The options of [`Study::join_sheet`].
#[derive(Debug, Clone)]
pub struct JoinOptions {
    /// Diagnose the recalibrated model and keep what it says (true).
    pub diagnose: bool,
}

impl Default for JoinOptions {
    fn default() -> Self {
        JoinOptions { diagnose: true }
    }
}

/// One model of the study on the data before the sheet and after it.
#[derive(Debug, Clone, PartialEq)]
pub struct Recalibrated {
    /// `start` (the base model) or the step's effect.
    pub what: String,
    pub before: Stats,
    pub after: Stats,
    /// The step now raises the error on the joined data.
    pub rises: bool,
}

/// What joining a sheet did.
#[derive(Debug, Clone)]
pub struct Joined {
    pub sheet: SheetRecord,
    /// Cases before the sheet joined.
    pub cases_before: usize,
    /// The start, then each step, before -> after.
    pub models: Vec<Recalibrated>,
}

fn refusal(study: &Path, e: SheetError) -> StudyError {
    StudyError::Sheet {
        file: study.to_path_buf(),
        error: e,
    }
}

/// A sheet read and parsed, with its hash. It must hold its whole setup
/// in its own columns: a sheet that reads another file (a CSV's
/// `# setup_file`) would join geometry no pin holds.
fn read_sheet(study: &Path, sheet: &Path) -> Result<(Dataset, Vec<u8>), StudyError> {
    let data_err = |message: String| StudyError::Data {
        file: study.to_path_buf(),
        message,
    };
    let bytes = crate::input_file::read(sheet, crate::input_file::cap::DATASET, "a run sheet")
        .map_err(|e| data_err(format!("{}: {e}", sheet.display())))?;
    let read = Inputs::new();
    let data = crate::data::load_recorded(sheet, &read).map_err(|e| data_err(e.to_string()))?;
    if let Some(other) = read
        .list()
        .into_iter()
        .find(|i| i.path != sheet.display().to_string())
    {
        return Err(data_err(format!(
            "{}: the sheet reads {}: a run sheet carries its setup in its own columns (as `swimbot plan` writes them), so that its one pin holds all it brings",
            sheet.display(),
            other.path
        )));
    }
    Ok((data, bytes))
}

/// `data` followed by the measured rows of the sheet at `sheet`, and the
/// sheet's bytes.
fn joined_rows(
    study: &Path,
    data: &Dataset,
    sheet: &Path,
) -> Result<(Merged, Vec<u8>), StudyError> {
    let (rows, bytes) = read_sheet(study, sheet)?;
    let merged = merge(data, &rows, &sheet.display().to_string()).map_err(|e| refusal(study, e))?;
    Ok((merged, bytes))
}

/// The pinned dataset followed by every pinned sheet, each checked
/// against its hash and its recorded rows; the sheets' bytes recorded in
/// `inputs`.
pub(super) fn load_joined(
    study: &Path,
    sheets: &[SheetRecord],
    mut data: Dataset,
    inputs: &Inputs,
) -> Result<Dataset, StudyError> {
    for s in sheets {
        let path = resolve(study, &s.path);
        let (merged, bytes) = joined_rows(study, &data, &path)?;
        let sha = sha256_hex(&bytes);
        if sha != s.sha256 {
            return Err(StudyError::InputChanged {
                file: study.to_path_buf(),
                input: path.clone(),
                message: format!(
                    "the run sheet {} changed since it joined the study (SHA-256 {sha}, pinned {}): every step was calibrated with its rows. Restore the sheet, or start the study again",
                    path.display(),
                    s.sha256
                ),
            });
        }
        if merged.joined != s.cases {
            return Err(StudyError::Unverified {
                file: study.to_path_buf(),
                at: format!("the sheet {}", path.display()),
                field: "dataset.sheet.cases".into(),
                message: format!(
                    "stored [{}], but the sheet's measured rows are [{}]",
                    s.cases.join(", "),
                    merged.joined.join(", ")
                ),
            });
        }
        inputs.record(&path, &bytes);
        data = merged.data;
    }
    Ok(data)
}

impl Study {
    /// Join the run sheet at `sheet` to the study's data, recalibrate
    /// every step on the joined data, diagnose again and write the study
    /// (module docs). A refusal (another robot's row, a changed tail, a
    /// taken id, a sheet already joined) names the row and the field and
    /// writes nothing.
    pub fn join_sheet(&mut self, sheet: &Path, o: &JoinOptions) -> Result<Joined, StudyError> {
        // A sheet joined twice would fail on its ids; say what happened.
        let sha256 = crate::input_file::read(sheet, crate::input_file::cap::DATASET, "a run sheet")
            .map(|b| sha256_hex(&b))
            .unwrap_or_default();
        if let Some(s) = self.file.dataset.sheets.iter().find(|s| s.sha256 == sha256) {
            return Err(StudyError::Data {
                file: self.path.clone(),
                message: format!(
                    "{}: this sheet (SHA-256 {sha256}) already joined the study as {}",
                    sheet.display(),
                    s.path.display()
                ),
            });
        }
        let (merged, bytes) = joined_rows(&self.path, &self.data, sheet)?;
        let record = SheetRecord {
            path: stored_path(&self.path, sheet),
            sha256: sha256_hex(&bytes),
            cases: merged.joined,
            skipped: merged.skipped,
            joined_utc: now_utc(),
        };
        let cases_before = self.data.cases.len();
        let mut next = self.clone();
        next.data = merged.data;
        next.file.dataset.sheets.push(record.clone());
        let models = next.recalibrate_from(self, &record, o)?;
        let sha = next.file.write_over(&self.path, &self.opened_sha256)?;
        next.opened_sha256 = sha;
        next.inputs.record(sheet, &bytes);
        *self = next;
        Ok(Joined {
            sheet: record,
            cases_before,
            models,
        })
    }

    /// Rebuild the start and every step of `old` on this study's data.
    fn recalibrate_from(
        &mut self,
        old: &Study,
        sheet: &SheetRecord,
        o: &JoinOptions,
    ) -> Result<Vec<Recalibrated>, StudyError> {
        let model_err = |m: String| StudyError::Model {
            file: self.path.clone(),
            message: m,
        };
        let lik = self.likelihood()?;
        self.file.start = Snapshot::of(&self.base_model()?, &self.data, &[])
            .map_err(|e| model_err(e.to_string()))?;
        self.file.first_diagnosis = None;
        self.file.steps.clear();
        let mut models = vec![Recalibrated {
            what: "start".into(),
            before: old.file.start.stats,
            after: self.file.start.stats,
            rises: false,
        }];
        let note = format!(
            "recalibrated when the run sheet {} joined the data ({} runs)",
            sheet.path.display(),
            sheet.cases.len()
        );
        for (i, was) in old.file.steps.iter().enumerate() {
            let opts = AddOptions {
                refit_all: was.refit == "all" && was.choice.is_none(),
                force: true,
                diagnose: false,
            };
            let mut rec =
                self.step_record(was.effect.clone(), &opts)
                    .map_err(|e| StudyError::Step {
                        file: self.path.clone(),
                        step: i + 1,
                        effect: was.effect.name.clone(),
                        field: "effect".into(),
                        message: format!("it cannot be recalibrated on the joined data: {e}"),
                    })?;
            rec.proposed_by = was.proposed_by.clone();
            rec.notes.push(note.clone());
            models.push(Recalibrated {
                what: was.effect.name.clone(),
                before: was.after.stats,
                after: rec.after.stats,
                rises: rec.forced,
            });
            self.file.steps.push(rec);
        }
        if o.diagnose {
            let d = DiagnosisRecord::run(&self.model()?, &self.data, lik)
                .map_err(|e| model_err(e.to_string()))?;
            match self.file.steps.last_mut() {
                Some(s) => s.diagnosis_after = Some(d),
                None => self.file.first_diagnosis = Some(d),
            }
        }
        Ok(models)
    }
}
