//! The study file: TOML, human-readable, with a schema version, written
//! atomically (a temporary file beside it, then a rename, so that a crash
//! leaves the old study or the new one, never half of one) under the
//! output rules of [`crate::atomic_file`].
//! docs/study.md documents every field.

use super::definition::Definition;
use super::diagnosis::DiagnosisRecord;
use super::error::StudyError;
use super::snapshot::{Snapshot, Stats};
use crate::workbench::fit::profile::ProfileInterval;
use crate::workbench::fit::report::ParamReport;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// The schema this version writes and reads.
pub const SCHEMA: u32 = 1;

/// The name `init` gives the study in the working directory, and the file
/// the commands look for there.
pub const DEFAULT_FILE: &str = "swimbot-study.toml";

/// The whole file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StudyFile {
    pub schema: u32,
    /// The swimbot that started the study.
    pub swimbot_version: String,
    /// When it was started, RFC 3339 UTC.
    pub created_utc: String,
    pub dataset: DatasetRef,
    pub model: BaseModel,
    /// The base model on the data, before any step.
    pub start: Snapshot,
    /// What `diagnose` said of the base model.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub first_diagnosis: Option<DiagnosisRecord>,
    #[serde(default, rename = "step")]
    pub steps: Vec<StepRecord>,
}

/// The data the study is calibrated on.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DatasetRef {
    /// As given to `init`, relative to the study file's folder when it was
    /// given relative.
    pub path: PathBuf,
    /// SHA-256 of its bytes: a changed file is refused.
    pub sha256: String,
    /// The dataset's own name.
    pub name: String,
    /// Every other file the dataset reads (a CSV's `# setup_file`) and the
    /// SHA-256 of its bytes: a changed one is refused too.
    #[serde(default, rename = "pin", skip_serializing_if = "Vec::is_empty")]
    pub pins: Vec<super::pin::PinRecord>,
    /// Run sheets joined after it, in order: the study's data are the
    /// dataset's cases, then each sheet's rows.
    #[serde(default, rename = "sheet", skip_serializing_if = "Vec::is_empty")]
    pub sheets: Vec<super::sheets::SheetRecord>,
}

/// What the steps start from.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BaseModel {
    /// A named model (`base`, `paper`, `paper-lighthill`, `physics`).
    pub preset: String,
    /// What every fit minimises: `gaussian` (chi-square) or `student-t`.
    pub likelihood: String,
}

/// One parameter of a step.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ParamRecord {
    /// The effect it belongs to.
    pub effect: String,
    pub name: String,
    pub unit: String,
    pub value: f64,
    /// `fitted` (calibrated, with its 95 % interval), `fixed` (held at
    /// `value`, `reason` says why) or `setting` (not a free parameter).
    pub status: String,
    /// 95 % interval, for a fitted parameter.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lo: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub hi: Option<f64>,
    /// Standard uncertainty of a fitted parameter (the 95 % half-width
    /// over 1.96, before `lo`/`hi` are cut at the parameter's range).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub standard_uncertainty: Option<f64>,
    /// The fit ended on the parameter's bound.
    #[serde(default)]
    pub at_bound: bool,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reason: Option<String>,
    /// The profile likelihood's 95 % interval of a fitted parameter of the
    /// step's own effect ([`crate::workbench::fit::profile`]), absent where
    /// it was not computed (an earlier swimbot, a refitted parameter, a
    /// profile whose refit failed).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub profile: Option<ProfileRecord>,
}

/// A parameter's profile-likelihood interval as the study stores it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ProfileRecord {
    /// The ends; an end absent is open (the profiled deviance stays below
    /// the threshold up to the parameter's range). TOML has no null, so an
    /// open end is a missing key.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub low: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub high: Option<f64>,
    /// Whether an end differs from the covariance's by more than
    /// [`crate::workbench::fit::profile::ASYMMETRY`] of its half-width:
    /// the profile is then the interval reported.
    pub asymmetric: bool,
}

impl ProfileRecord {
    /// The record of a computed profile.
    pub fn of(p: &ProfileInterval) -> Self {
        ProfileRecord {
            low: p.low,
            high: p.high,
            asymmetric: p.asymmetric,
        }
    }
}

impl ParamRecord {
    /// The parameter as the fit's report has it: its value and standard
    /// uncertainty as stored; the 95 % interval the profile's where that
    /// one is asymmetric (as `diagnose` reports it,
    /// [`ParamReport::with_profile`]), else the covariance's as stored
    /// (cut at the parameter's range).
    pub fn report(&self) -> ParamReport {
        let r = self.covariance_report();
        match &self.profile {
            Some(p) => r.with_profile(&ProfileInterval {
                value: self.value,
                low: p.low,
                high: p.high,
                covariance_low: self.lo,
                covariance_high: self.hi,
                asymmetric: p.asymmetric,
            }),
            None => r,
        }
    }

    fn covariance_report(&self) -> ParamReport {
        let u = self.standard_uncertainty;
        ParamReport {
            name: self.name.clone(),
            unit: self.unit.clone(),
            value: self.value,
            standard_uncertainty: u,
            relative_uncertainty_percent: u
                .filter(|_| self.value != 0.0)
                .map(|u| 100.0 * u / self.value.abs()),
            ci95_low: self.lo,
            ci95_high: self.hi,
            interval: "covariance".into(),
            at_bound: self.at_bound,
        }
    }
}

/// One step: an effect added on top of the steps before it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StepRecord {
    pub effect: Definition,
    /// `held` (earlier steps kept their values) or `all` (refitted jointly).
    pub refit: String,
    /// Both calibrations `add` tried (earlier steps held, every step
    /// refitted) and why it kept the one it kept; absent when there was
    /// nothing earlier to refit or `--refit-all` asked for the joint one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub choice: Option<super::refit::RefitChoice>,
    /// This step's parameters, every one of them.
    #[serde(rename = "param")]
    pub params: Vec<ParamRecord>,
    /// Earlier steps' parameters a joint refit changed (their new values).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub refitted: Vec<ParamRecord>,
    /// What the calibration says in words (held, reduced, at a bound).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub notes: Vec<String>,
    /// The model before, as recorded in the study (the previous step's after).
    pub before: Stats,
    pub after: Snapshot,
    /// The diagnosis that proposed it, when it did.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub proposed_by: Option<String>,
    /// What `diagnose` says of the model with this step.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub diagnosis_after: Option<DiagnosisRecord>,
    /// Recorded with `add --force` although the error rose.
    #[serde(default)]
    pub forced: bool,
    pub swimbot_version: String,
    pub date_utc: String,
}

impl StudyFile {
    /// Read and check a study file.
    pub fn read(path: &Path) -> Result<Self, StudyError> {
        Self::read_hashed(path).map(|(f, _)| f)
    }

    /// Read and check a study file; also the SHA-256 of its bytes, which
    /// [`StudyFile::write_over`] checks before replacing it. Bounded by
    /// [`crate::input_file::cap::STUDY`] while reading (a study pointed at `/dev/zero` or a
    /// FIFO costs the cap, never the machine).
    pub fn read_hashed(path: &Path) -> Result<(Self, String), StudyError> {
        let (file, text) = Self::read_with_text(path)?;
        Ok((file, crate::provenance::sha256_hex(text.as_bytes())))
    }

    /// Read and check a study file; also its text as read.
    pub fn read_with_text(path: &Path) -> Result<(Self, String), StudyError> {
        use crate::input_file::{cap, read_text, ReadError};
        let text = read_text(path, cap::STUDY, "a study file").map_err(|e| match e {
            ReadError::Io(_) if !path.exists() && !path.is_symlink() => StudyError::NotFound {
                file: path.to_path_buf(),
            },
            e => StudyError::Format {
                file: path.to_path_buf(),
                field: "(file)".into(),
                message: e.to_string(),
            },
        })?;
        Ok((Self::parse(&text, path)?, text))
    }

    /// Parse a study's text; `path` names it in errors.
    pub fn parse(text: &str, path: &Path) -> Result<Self, StudyError> {
        // The schema first, so that a newer study says so rather than
        // failing on a field this version does not know.
        let schema = text
            .parse::<toml::Table>()
            .ok()
            .and_then(|t| t.get("schema")?.as_integer());
        if let Some(s) = schema.filter(|s| *s != i64::from(SCHEMA)) {
            return Err(StudyError::Format {
                file: path.to_path_buf(),
                field: "schema".into(),
                message: format!(
                    "schema {s}; this swimbot ({}) reads schema {SCHEMA}",
                    env!("CARGO_PKG_VERSION")
                ),
            });
        }
        toml::from_str(text).map_err(|e| {
            let field = e
                .message()
                .split('`')
                .nth(1)
                .unwrap_or("(syntax)")
                .to_string();
            let at = e
                .span()
                .map(|s| {
                    let line = text[..s.start.min(text.len())].matches('\n').count() + 1;
                    format!("line {line}: ")
                })
                .unwrap_or_default();
            StudyError::Format {
                file: path.to_path_buf(),
                field,
                message: format!("{at}{}", e.message().trim()),
            }
        })
    }

    /// The file's text.
    pub fn to_text(&self) -> String {
        let body = toml::to_string(self).expect("a study serialises to TOML");
        format!(
            "# swimbot study: the model built step by step on one dataset.\n\
             # Written by swimbot; read by every swimbot command run in this folder.\n\
             # Fields: docs/study.md. Edit with `swimbot add` and `swimbot undo`.\n\n{body}"
        )
    }

    /// Write atomically under the rules of every output
    /// ([`crate::atomic_file`]): a temporary file in the same folder,
    /// flushed to disk, renamed over `path`; a symbolic link is followed,
    /// a FIFO, device or directory refused. Returns the SHA-256 of the
    /// text written.
    pub fn write(&self, path: &Path) -> Result<String, StudyError> {
        let text = self.to_text();
        crate::atomic_file::replace(path, text.as_bytes()).map_err(|message| StudyError::Io {
            file: path.to_path_buf(),
            message,
        })?;
        Ok(crate::provenance::sha256_hex(text.as_bytes()))
    }

    /// [`StudyFile::write`], but only over the study this process read
    /// (its bytes' SHA-256 `expected`): a study another command changed
    /// meanwhile (two `add`s run at once, an `undo` during an `add`) is
    /// refused rather than overwritten, so that no recorded step is lost.
    /// An exclusive `flock` on the file is held from the check to the
    /// rename; a writer that waited for it finds the file replaced.
    pub fn write_over(&self, path: &Path, expected: &str) -> Result<String, StudyError> {
        let changed = || StudyError::Changed {
            file: path.to_path_buf(),
        };
        let current = std::fs::File::open(path).map_err(|_| changed())?;
        lock_exclusive(&current).map_err(|e| StudyError::Io {
            file: path.to_path_buf(),
            message: format!("cannot lock it: {e}"),
        })?;
        if !same_file(&current, path) {
            return Err(changed());
        }
        let mut bytes = Vec::new();
        std::io::Read::read_to_end(
            &mut std::io::Read::take(&current, crate::input_file::cap::STUDY + 1),
            &mut bytes,
        )
        .map_err(|_| changed())?;
        if crate::provenance::sha256_hex(&bytes) != expected {
            return Err(changed());
        }
        // The lock is released when `current` is closed, after the rename.
        let written = self.write(path);
        drop(current);
        written
    }
}

#[cfg(unix)]
fn lock_exclusive(f: &std::fs::File) -> std::io::Result<()> {
    use std::os::unix::io::AsRawFd;
    // SAFETY: flock on a descriptor `f` owns; released when it is closed.
    if unsafe { libc::flock(f.as_raw_fd(), libc::LOCK_EX) } == 0 {
        Ok(())
    } else {
        Err(std::io::Error::last_os_error())
    }
}

#[cfg(not(unix))]
fn lock_exclusive(_: &std::fs::File) -> std::io::Result<()> {
    Ok(())
}

/// Whether the open file `f` is still the one at `path` (not renamed over).
#[cfg(unix)]
fn same_file(f: &std::fs::File, path: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    match (f.metadata(), std::fs::metadata(path)) {
        (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
        _ => false,
    }
}

#[cfg(not(unix))]
fn same_file(_: &std::fs::File, _: &Path) -> bool {
    true
}
