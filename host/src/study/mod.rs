//! The study: the user's model as one file that every command reads and
//! writes, as `Cargo.toml` is for cargo. It pins the dataset (path and
//! SHA-256), names the base model and the likelihood, and keeps the
//! ordered steps, each an effect added on top of the ones before with its
//! definition (formula, statement, reference), its calibrated parameters
//! with 95 % intervals, the model's statistics before and after (MARE,
//! cross-validated MARE, chi-square, noise floor), the diagnosis that
//! proposed it and the one after it, the swimbot version and the date.
//!
//! [`Study`] is the library's whole interface: [`Study::init`],
//! [`Study::open`], [`Study::add`], [`Study::undo`], [`Study::steps`],
//! [`Study::model`] and [`Study::apply_to`] (the study's models with their
//! parameters held, on other data). No command-line type appears in it;
//! the CLI (`swimbot init`, `add`, `steps`, `undo`) and the page are thin
//! layers over it. The file format is in docs/study.md.

mod calibrate;
pub mod data_add;
pub mod definition;
pub mod diagnosis;
mod error;
pub mod file;
pub mod pin;
pub mod refit;
pub mod sheets;
pub mod snapshot;
pub mod verify;

pub use definition::Definition;
pub use diagnosis::DiagnosisRecord;
pub use error::{ParamValueError, StudyError};
pub use file::{StepRecord, StudyFile, DEFAULT_FILE, SCHEMA};
pub use pin::PinRecord;
pub use refit::{RefitChoice, Trial};
pub use sheets::{JoinOptions, Joined, Recalibrated, SheetRecord};
pub use snapshot::{CaseRow, Snapshot, Stats};

use crate::data::Dataset;
use crate::effects::{Catalogue, EffectInstance};
use crate::model::{preset, Model};
use crate::provenance::Inputs;
use crate::workbench::robust::Likelihood;
use serde::Serialize;
use std::path::{Path, PathBuf};

/// The options of [`Study::init`].
#[derive(Debug, Clone)]
pub struct InitOptions {
    /// The base model's preset (`base` by default).
    pub preset: String,
    pub likelihood: Likelihood,
    /// Replace a study already at the path.
    pub force: bool,
    /// Run `diagnose` on the base model and keep what it says (true).
    pub diagnose: bool,
}

impl Default for InitOptions {
    fn default() -> Self {
        InitOptions {
            preset: "base".into(),
            likelihood: Likelihood::Gaussian,
            force: false,
            diagnose: true,
        }
    }
}

/// The options of [`Study::add`].
#[derive(Debug, Clone)]
pub struct AddOptions {
    /// Refit every step's parameters jointly (false: earlier steps held).
    pub refit_all: bool,
    /// Record the step even if the error rises.
    pub force: bool,
    /// Run `diagnose` on the new model and keep what it says (true).
    pub diagnose: bool,
}

impl Default for AddOptions {
    fn default() -> Self {
        AddOptions {
            refit_all: false,
            force: false,
            diagnose: true,
        }
    }
}

/// An open study: its file, where it is, and its dataset (checked against
/// the pinned SHA-256).
#[derive(Debug, Clone)]
pub struct Study {
    path: PathBuf,
    file: StudyFile,
    data: Dataset,
    /// SHA-256 of the file's bytes as this process last read or wrote
    /// them: a write over anything else is refused (`StudyFile::write_over`).
    opened_sha256: String,
    /// The files the study read (its dataset, a CSV's setup file): the
    /// inputs of what is made from it (its report).
    inputs: Inputs,
}

/// The study's models on other data, parameters held.
#[derive(Debug, Clone, Serialize)]
pub struct Application {
    pub dataset: String,
    pub start: Snapshot,
    /// One per step, in order: the model up to and with it.
    pub steps: Vec<AppliedStep>,
}

/// One step on other data.
#[derive(Debug, Clone, Serialize)]
pub struct AppliedStep {
    pub effect: String,
    pub after: Snapshot,
}

/// `name` of a likelihood as the study file writes it.
pub fn likelihood_name(l: Likelihood) -> &'static str {
    match l {
        Likelihood::Gaussian => "gaussian",
        _ => "student-t",
    }
}

fn likelihood_of(name: &str) -> Option<Likelihood> {
    match name {
        "gaussian" => Some(Likelihood::Gaussian),
        "student-t" => Some(Likelihood::StudentT),
        _ => None,
    }
}

fn now_utc() -> String {
    humantime::format_rfc3339_seconds(std::time::SystemTime::now()).to_string()
}

impl Study {
    /// The study file to use: `explicit`, else [`DEFAULT_FILE`] in `dir`
    /// when there is one.
    pub fn locate(explicit: Option<&Path>, dir: &Path) -> Option<PathBuf> {
        match explicit {
            Some(p) => Some(p.to_path_buf()),
            None => Some(dir.join(DEFAULT_FILE)).filter(|p| p.is_file()),
        }
    }

    /// Start a study at `path` on the dataset at `data_path`: the base
    /// model's comparison (and diagnosis) recorded, the file written.
    pub fn init(path: &Path, data_path: &Path, o: &InitOptions) -> Result<Study, StudyError> {
        replaceable(path, o.force)?;
        let inputs = Inputs::new();
        let (data, sha256) = load_pinned(path, data_path, &inputs)?;
        not_an_input(path, &inputs)?;
        let pins = pin::pins_of(path, data_path, &inputs);
        let model = preset(&o.preset).ok_or_else(|| StudyError::Format {
            file: path.to_path_buf(),
            field: "model.preset".into(),
            message: format!(
                "unknown preset `{}`; known: {}",
                crate::data::limits::echo(&o.preset),
                crate::model::PRESETS
                    .iter()
                    .map(|p| p.0)
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        })?;
        let model_err = |m: String| StudyError::Model {
            file: path.to_path_buf(),
            message: m,
        };
        let start = Snapshot::of(&model, &data, &[]).map_err(|e| model_err(e.to_string()))?;
        let measured = data.measured_cases();
        if measured < 2 {
            // A step calibrated on one case passes through it exactly, and
            // its cross-validation has nothing to hold out.
            return Err(StudyError::Data {
                file: path.to_path_buf(),
                message: format!(
                    "{}: {measured} of its {} cases has a measured speed or rotation rate: a study calibrates its steps on measurements and needs at least 2 measured cases",
                    data_path.display(),
                    data.cases.len()
                ),
            });
        }
        let first_diagnosis = if o.diagnose {
            Some(
                DiagnosisRecord::run(&model, &data, o.likelihood)
                    .map_err(|e| model_err(e.to_string()))?,
            )
        } else {
            None
        };
        let file = StudyFile {
            schema: SCHEMA,
            swimbot_version: env!("CARGO_PKG_VERSION").into(),
            created_utc: now_utc(),
            dataset: file::DatasetRef {
                path: stored_path(path, data_path),
                sha256,
                name: data.name.clone(),
                pins,
                sheets: Vec::new(),
            },
            model: file::BaseModel {
                preset: o.preset.clone(),
                likelihood: likelihood_name(o.likelihood).into(),
            },
            start,
            first_diagnosis,
            steps: Vec::new(),
        };
        let opened_sha256 = file.write(path)?;
        Ok(Study {
            path: path.to_path_buf(),
            file,
            data,
            opened_sha256,
            inputs,
        })
    }

    /// Open the study at `path`: its dataset loaded and checked against
    /// the pinned SHA-256, every step's effect rebuilt.
    pub fn open(path: &Path) -> Result<Study, StudyError> {
        let (file, text) = StudyFile::read_with_text(path)?;
        let opened_sha256 = crate::provenance::sha256_hex(text.as_bytes());
        let data_path = resolve(path, &file.dataset.path);
        let inputs = Inputs::new();
        let (data, sha256) = load_pinned(path, &data_path, &inputs)?;
        if sha256 != file.dataset.sha256 {
            return Err(StudyError::DatasetChanged {
                file: path.to_path_buf(),
                data: data_path,
                expected: file.dataset.sha256.clone(),
                found: sha256,
            });
        }
        pin::check(path, &file.dataset.pins, &data_path, &inputs)?;
        let data = sheets::load_joined(path, &file.dataset.sheets, data, &inputs)?;
        // The study is an input of what is made from it (its provenance,
        // and the output guard: no output may replace it).
        inputs.record(path, text.as_bytes());
        let study = Study {
            path: path.to_path_buf(),
            file,
            data,
            opened_sha256,
            inputs,
        };
        study.likelihood()?;
        study.model()?;
        verify::verify(&study)?;
        Ok(study)
    }

    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The files the study has read (its dataset, a CSV's setup file).
    pub fn inputs(&self) -> &Inputs {
        &self.inputs
    }

    pub fn file(&self) -> &StudyFile {
        &self.file
    }

    pub fn dataset(&self) -> &Dataset {
        &self.data
    }

    /// The dataset's path as the study resolves it.
    pub fn dataset_path(&self) -> PathBuf {
        resolve(&self.path, &self.file.dataset.path)
    }

    pub fn steps(&self) -> &[StepRecord] {
        &self.file.steps
    }

    pub fn likelihood(&self) -> Result<Likelihood, StudyError> {
        likelihood_of(&self.file.model.likelihood).ok_or_else(|| StudyError::Format {
            file: self.path.clone(),
            field: "model.likelihood".into(),
            message: format!(
                "`{}` is not a likelihood: gaussian or student-t",
                crate::data::limits::echo(&self.file.model.likelihood)
            ),
        })
    }

    /// The model now: the base with every step.
    pub fn model(&self) -> Result<Model, StudyError> {
        self.model_upto(self.file.steps.len())
    }

    /// The base model alone.
    pub fn base_model(&self) -> Result<Model, StudyError> {
        self.model_upto(0)
    }

    /// The base with the first `k` steps, each at its values then (a later
    /// joint refit's values apply from its step on).
    pub fn model_upto(&self, k: usize) -> Result<Model, StudyError> {
        Ok(self.model_and_catalogue(k)?.0)
    }

    /// The effects the study knows: the compiled-in ones and its steps'
    /// user effects (each study its own, whatever others a process opened).
    pub fn catalogue(&self) -> Result<Catalogue, StudyError> {
        Ok(self.model_and_catalogue(self.file.steps.len())?.1)
    }

    /// The base with the first `k` steps, and the catalogue their effects
    /// were registered in.
    fn model_and_catalogue(&self, k: usize) -> Result<(Model, Catalogue), StudyError> {
        let mut catalogue = Catalogue::builtin();
        let mut model = preset(&self.file.model.preset).ok_or_else(|| StudyError::Format {
            file: self.path.clone(),
            field: "model.preset".into(),
            message: format!(
                "unknown preset `{}`",
                crate::data::limits::echo(&self.file.model.preset)
            ),
        })?;
        for (i, s) in self.file.steps[..k.min(self.file.steps.len())]
            .iter()
            .enumerate()
        {
            let err = |field: &str, message: String| StudyError::Step {
                file: self.path.clone(),
                step: i + 1,
                effect: s.effect.name.clone(),
                field: field.into(),
                message,
            };
            let effect = s
                .effect
                .effect(&mut catalogue)
                .map_err(|m| err("effect", m.to_string()))?;
            if model.effects.iter().any(|e| e.name() == effect.name()) {
                return Err(err(
                    "effect",
                    format!(
                        "`{}` is already in the model before this step (a step repeated?): an effect applied twice is not a model",
                        effect.name()
                    ),
                ));
            }
            let mut inst = EffectInstance::default_of(effect);
            set_values(&mut inst, &s.params).map_err(|m| err("param", m.to_string()))?;
            model.effects.push(inst);
            for r in &s.refitted {
                let e = model
                    .effects
                    .iter_mut()
                    .find(|e| e.name() == r.effect)
                    .ok_or_else(|| err("refitted", format!("no earlier step `{}`", r.effect)))?;
                set_values(e, std::slice::from_ref(r))
                    .map_err(|m| err("refitted", m.to_string()))?;
            }
        }
        Ok((model, catalogue))
    }

    /// The statistics of the model now (the last step's after, or the start's).
    pub fn current(&self) -> &Snapshot {
        self.file
            .steps
            .last()
            .map_or(&self.file.start, |s| &s.after)
    }

    /// What `diagnose` said last (after the last step, or of the base).
    pub fn last_diagnosis(&self) -> Option<&DiagnosisRecord> {
        match self.file.steps.last() {
            Some(s) => s.diagnosis_after.as_ref(),
            None => self.file.first_diagnosis.as_ref(),
        }
    }

    /// Add `def` as a new step: calibrate it on top of the current model,
    /// refuse it when the error (MARE) rises unless `o.force`, record it
    /// and write the file.
    pub fn add(&mut self, def: Definition, o: &AddOptions) -> Result<&StepRecord, StudyError> {
        let record = self.step_record(def, o)?;
        self.file.steps.push(record);
        match self.file.write_over(&self.path, &self.opened_sha256) {
            Ok(sha) => self.opened_sha256 = sha,
            Err(e) => {
                self.file.steps.pop();
                return Err(e);
            }
        }
        Ok(self.file.steps.last().expect("just pushed"))
    }

    /// The step `def` would be on top of the current model (what
    /// [`Study::add`] records), the file untouched.
    fn step_record(&self, def: Definition, o: &AddOptions) -> Result<StepRecord, StudyError> {
        let eff_err = |m: String| StudyError::Effect {
            file: self.path.clone(),
            effect: def.name.clone(),
            message: m,
        };
        let effect = def
            .effect(&mut self.catalogue()?)
            .map_err(|e| eff_err(e.to_string()))?;
        let before_model = self.model()?;
        if let Some(i) = before_model
            .effects
            .iter()
            .position(|e| e.name() == def.name)
        {
            let first = before_model.effects.len() - self.file.steps.len();
            let where_ = match i.checked_sub(first) {
                Some(k) => format!("step {}", k + 1),
                None => format!("the `{}` preset", self.file.model.preset),
            };
            return Err(eff_err(format!("it is already in the model ({where_})")));
        }
        if !before_model.can_take(&*effect) {
            let mut with = before_model.clone();
            with.effects.push(EffectInstance::default_of(effect));
            let why = with
                .check_tail_compat()
                .err()
                .map_or_else(|| "it conflicts with the model".into(), |e| e.to_string());
            return Err(eff_err(why));
        }
        let first_step = before_model.effects.len() - self.file.steps.len();
        let mut model = before_model.clone();
        model.effects.push(EffectInstance::default_of(effect));
        let lik = self.likelihood()?;
        let model_err = |m: String| StudyError::Model {
            file: self.path.clone(),
            message: format!("`{}`: {m}", def.name),
        };
        let (mut c, choice) =
            self.calibrate_step(model, first_step, o.refit_all, lik, &model_err)?;
        let after =
            Snapshot::of(&c.model, &self.data, &c.fitted).map_err(|e| model_err(e.to_string()))?;
        if !after.is_finite() {
            return Err(model_err(
                "the calibrated model predicts a non-finite value".into(),
            ));
        }
        let before = self.current().stats;
        if after.stats.mare > before.mare && !o.force {
            return Err(StudyError::ErrorRises {
                file: self.path.clone(),
                effect: def.name.clone(),
                before_pct: 100.0 * before.mare,
                after_pct: 100.0 * after.stats.mare,
                chi2_before: before.chi2,
                chi2_after: after.stats.chi2,
                tried: rise_advice(choice.as_ref(), &self.file.steps),
            });
        }
        // After the refusal: a profile costs tens of refits per parameter.
        calibrate::profile_new(&mut c, &self.data, lik);
        let proposed_by = self.last_diagnosis().and_then(|d| {
            d.proposal_for(&def.name, &def.formula).map(|p| {
                format!(
                    "diagnose ({}) on the model before this step: {}",
                    d.verdict, p.text
                )
            })
        });
        let diagnosis_after = if o.diagnose {
            Some(
                DiagnosisRecord::run(&c.model, &self.data, lik)
                    .map_err(|e| model_err(e.to_string()))?,
            )
        } else {
            None
        };
        let forced = after.stats.mare > before.mare;
        let joint = o.refit_all || choice.as_ref().is_some_and(|c| c.kept == "joint");
        Ok(StepRecord {
            effect: def,
            refit: if joint { "all" } else { "held" }.into(),
            choice,
            params: c.params,
            refitted: c.refitted,
            notes: c.notes,
            before,
            after,
            proposed_by,
            diagnosis_after,
            forced,
            swimbot_version: env!("CARGO_PKG_VERSION").into(),
            date_utc: now_utc(),
        })
    }

    /// Calibrate the new (last) effect of `model`: held, jointly refitted,
    /// or both and the better kept by the rule of [`refit`].
    fn calibrate_step(
        &self,
        model: Model,
        first_step: usize,
        refit_all: bool,
        lik: Likelihood,
        model_err: &dyn Fn(String) -> StudyError,
    ) -> Result<(calibrate::Calibrated, Option<RefitChoice>), StudyError> {
        let new = model.effects.len() - 1;
        let earlier: Vec<usize> = (first_step..new).collect();
        let raw =
            |joint: bool| calibrate::calibrate(model.clone(), first_step, joint, &self.data, lik);
        let cal = |joint: bool| raw(joint).map_err(|e| model_err(e.to_string()));
        if refit_all || crate::workbench::fit::free_params_of(&model, &earlier).is_empty() {
            return Ok((cal(refit_all)?, None));
        }
        let held = cal(false)?;
        // The joint refit is a second opinion: when it fails, the held
        // fit stands, and the note says what was tried.
        let joint = match raw(true) {
            Ok(j) => j,
            Err(e) => {
                let mut held = held;
                held.notes.push(format!(
                    "a joint refit of every step was tried and failed ({e}); the earlier steps are held at their values"
                ));
                return Ok((held, None));
            }
        };
        let trial = |c: &calibrate::Calibrated| {
            Trial::of(c, &self.data).map_err(|e| model_err(e.to_string()))
        };
        let (keep_joint, choice) = refit::choose(
            trial(&held)?,
            trial(&joint)?,
            self.current().stats.mare,
            self.current().stats.n,
        );
        let mut kept = if keep_joint { joint } else { held };
        kept.notes
            .insert(1.min(kept.notes.len()), choice.reason.clone());
        Ok((kept, Some(choice)))
    }

    /// Remove the last step (and what its joint refit changed) and write
    /// the file; returns the removed step.
    pub fn undo(&mut self) -> Result<StepRecord, StudyError> {
        let last = self
            .file
            .steps
            .pop()
            .ok_or_else(|| StudyError::NothingToUndo {
                file: self.path.clone(),
            })?;
        match self.file.write_over(&self.path, &self.opened_sha256) {
            Ok(sha) => self.opened_sha256 = sha,
            Err(e) => {
                self.file.steps.push(last);
                return Err(e);
            }
        }
        Ok(last)
    }

    /// The study's models (the base, then each step) on `data` with every
    /// parameter held at the study's values: calibrated on the study's
    /// data, predicting these.
    pub fn apply_to(&self, data: &Dataset) -> Result<Application, StudyError> {
        let err = |m: String| StudyError::Model {
            file: self.path.clone(),
            message: format!("{}: {m}", data.name),
        };
        let start = Snapshot::of(&self.base_model()?, data, &[]).map_err(|e| err(e.to_string()))?;
        if start.stats.n == 0 {
            return Err(err(
                "no case has a measured speed or rotation rate: there is no error to compute on these data".into(),
            ));
        }
        let mut steps = Vec::new();
        for (k, s) in self.file.steps.iter().enumerate() {
            let m = self.model_upto(k + 1)?;
            steps.push(AppliedStep {
                effect: s.effect.name.clone(),
                after: Snapshot::of(&m, data, &[]).map_err(|e| err(e.to_string()))?,
            });
        }
        Ok(Application {
            dataset: data.name.clone(),
            start,
            steps,
        })
    }
}

/// What to say when the kept calibration raises the error: both tries'
/// numbers, and that an earlier step may be standing in for this effect.
fn rise_advice(choice: Option<&RefitChoice>, steps: &[StepRecord]) -> String {
    let Some(c) = choice else {
        return String::new();
    };
    let last = steps.last().map_or("", |s| s.effect.name.as_str());
    format!(
        "; with earlier steps held MARE {:.2} %, refitted jointly {:.2} %: if an earlier step absorbed what this effect explains, `swimbot undo` it ({last}) and add this effect first",
        100.0 * c.held.mare,
        100.0 * c.joint.mare
    )
}

/// Set `inst`'s parameters from records, by name.
fn set_values(
    inst: &mut EffectInstance,
    records: &[file::ParamRecord],
) -> Result<(), ParamValueError> {
    for r in records {
        let specs = inst.effect.params();
        let i = specs.iter().position(|p| p.name == r.name).ok_or_else(|| {
            ParamValueError::Unknown {
                effect: inst.name().to_string(),
                param: crate::data::limits::echo(&r.name).to_string(),
            }
        })?;
        let p = &specs[i];
        if !(r.value.is_finite() && r.value >= p.min && r.value <= p.max) {
            return Err(ParamValueError::OutOfRange {
                effect: inst.name().to_string(),
                param: p.name.to_string(),
                value: r.value,
                min: p.min,
                max: p.max,
            });
        }
        inst.values[i] = r.value;
    }
    Ok(())
}

/// Whether `init` may write a study at `path`: nothing there; or, with
/// `force`, a study (a regular file, or a link to one, whose TOML has a
/// `schema`): `--force` starts a study again, it never replaces a FIFO, a
/// device, a dataset or any other file.
fn replaceable(path: &Path, force: bool) -> Result<(), StudyError> {
    let exists = path.exists() || path.is_symlink();
    if !exists {
        return Ok(());
    }
    if !force {
        return Err(StudyError::Exists {
            file: path.to_path_buf(),
        });
    }
    let io = |message: String| StudyError::Io {
        file: path.to_path_buf(),
        message,
    };
    crate::atomic_file::resolve(path).map_err(io)?;
    let text =
        crate::input_file::read_text(path, crate::input_file::cap::STUDY, "a study file").ok();
    let is_study = text
        .and_then(|t| t.parse::<toml::Table>().ok())
        .is_some_and(|t| t.contains_key("schema") && t.contains_key("dataset"));
    if !is_study {
        return Err(io(
            "is not a study file (no TOML `schema` and `[dataset]`): `init --force` replaces a study, never another file; name another --study, or move the file".into(),
        ));
    }
    Ok(())
}

/// The study at `path` is none of the files its dataset read (`--study
/// paper.csv`, `--study` naming the setup file): writing it would destroy them.
fn not_an_input(path: &Path, inputs: &Inputs) -> Result<(), StudyError> {
    let Ok(study) = std::fs::canonicalize(path) else {
        return Ok(());
    };
    for i in inputs.list() {
        if std::fs::canonicalize(&i.path).is_ok_and(|p| p == study) {
            return Err(StudyError::Io {
                file: path.to_path_buf(),
                message: format!(
                    "is {}, an input of the study (its dataset, or a file the dataset reads): writing the study there would destroy it; name another --study",
                    i.path
                ),
            });
        }
    }
    Ok(())
}

/// The dataset and the SHA-256 of its bytes, the files read recorded in `inputs`.
fn load_pinned(
    study: &Path,
    data_path: &Path,
    inputs: &Inputs,
) -> Result<(Dataset, String), StudyError> {
    // Bounded while reading, as every input (a dataset path edited to
    // /dev/zero costs the cap, not the machine).
    let bytes = crate::input_file::read(data_path, crate::input_file::cap::DATASET, "a dataset")
        .map_err(|e| StudyError::Data {
            file: study.to_path_buf(),
            message: format!("{}: {e}", data_path.display()),
        })?;
    let data = crate::data::load_recorded(data_path, inputs).map_err(|e| StudyError::Data {
        file: study.to_path_buf(),
        message: e.to_string(),
    })?;
    Ok((data, crate::provenance::sha256_hex(&bytes)))
}

/// The dataset path to store: relative to the study's folder when both
/// are relative paths (the study and its data then move together).
fn stored_path(study: &Path, data: &Path) -> PathBuf {
    if data.is_absolute() {
        return data.to_path_buf();
    }
    let dir = study.parent().unwrap_or(Path::new(""));
    let (Ok(d), Ok(f)) = (std::path::absolute(dir), std::path::absolute(data)) else {
        return data.to_path_buf();
    };
    f.strip_prefix(&d)
        .map_or_else(|_| f.clone(), Path::to_path_buf)
}

/// The stored dataset path, relative to the study's folder.
fn resolve(study: &Path, data: &Path) -> PathBuf {
    if data.is_absolute() {
        data.to_path_buf()
    } else {
        study.parent().unwrap_or(Path::new("")).join(data)
    }
}

#[cfg(test)]
mod tests;

#[cfg(test)]
mod profile_tests;
