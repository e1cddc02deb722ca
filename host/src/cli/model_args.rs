//! Model options shared by the subcommands, validated into a [`Model`].

use super::CliError;
use crate::data::{self, Dataset};
use crate::effects::Catalogue;
use crate::model::{preset, Model, TailMethod, PRESETS};
use crate::physics::coefficients::CoefficientSet;
use crate::physics::solve::Dofs;
use crate::provenance::Inputs;
use clap::{Args, ValueEnum};
use std::path::PathBuf;

/// The help of `--preset` (sim replaces it: there the robot file's model
/// is the default).
pub const PRESET_HELP: &str =
    "Named model: base, paper, paper-lighthill, physics [default: base]. \
    physics: the zero-parameter Stokes model, slow on first use, then cached";

#[derive(Args, Debug, Clone)]
pub struct ModelArgs {
    #[arg(long, help = PRESET_HELP)]
    pub preset: Option<String>,
    /// Local drag coefficient set [default: the preset's; gray-hancock for base].
    #[arg(long, value_enum)]
    pub coefficients: Option<CoefficientsArg>,
    /// Add an effect: NAME or NAME:param=value,... (repeatable; see `swimbot effects`).
    #[arg(long = "effect", value_name = "NAME[:k=v,...]")]
    pub effects: Vec<String>,
    #[command(flatten)]
    pub effect_files: EffectFiles,
    /// How eq. 3 is integrated along the tail: exact (closed form) or
    /// quadrature (numerical, --nodes-per-wavelength nodes).
    #[arg(long, value_enum, default_value = "exact")]
    pub method: MethodArg,
    /// Quadrature nodes per wavelength (with --method quadrature; the paper used 100).
    #[arg(long, default_value_t = 100, allow_negative_numbers = true, value_parser = crate::cli::count::whole::<usize>)]
    pub nodes_per_wavelength: usize,
    /// Tail hydrodynamics: local RFT (eq. 3), or non-local slender-body theory / regularized Stokeslets.
    #[arg(long, value_enum, default_value = "rft")]
    pub tail_model: TailModelArg,
    /// Segments per helix turn of the non-local tail models, sbt and stokeslets (12 is converged to 1 %).
    #[arg(long, default_value_t = 12, allow_negative_numbers = true, value_parser = crate::cli::count::whole::<usize>)]
    pub segments_per_turn: usize,
    /// Degrees of freedom: axial (x-translation and x-rotation, the paper) or all six.
    #[arg(long, value_enum, default_value = "axial")]
    pub dofs: DofsArg,
}

#[derive(ValueEnum, Clone, Copy, Debug)]
pub enum CoefficientsArg {
    GrayHancock,
    Lighthill,
}

#[derive(ValueEnum, Clone, Copy, Debug)]
pub enum MethodArg {
    /// Closed form.
    Exact,
    /// Numerical, --nodes-per-wavelength nodes.
    Quadrature,
}

#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum TailModelArg {
    /// Local resistive-force theory (eq. 3).
    Rft,
    /// Johnson's slender-body theory (non-local).
    Sbt,
    /// Regularized Stokeslets (non-local).
    Stokeslets,
}

impl TailModelArg {
    /// The value as typed on the command line.
    pub fn name(self) -> &'static str {
        match self {
            TailModelArg::Rft => "rft",
            TailModelArg::Sbt => "sbt",
            TailModelArg::Stokeslets => "stokeslets",
        }
    }
}

#[derive(ValueEnum, Clone, Copy, Debug)]
pub enum DofsArg {
    Axial,
    All,
}

/// `--effect-file FILE.toml`: user effects, loaded before anything names
/// them. (`--effects` was its name before; kept hidden for old scripts.)
#[derive(Args, Debug, Clone, Default)]
pub struct EffectFiles {
    /// Load user effects stated as formulas (repeatable; docs/effects-format.md).
    #[arg(long = "effect-file", alias = "effects", value_name = "FILE.toml")]
    pub files: Vec<PathBuf>,
    /// Effects known before the files are read: a study's user effects,
    /// when a command works on the study's model.
    #[arg(skip)]
    pub known: Catalogue,
}

impl EffectFiles {
    /// The compiled-in effects, the [`EffectFiles::known`] ones and the
    /// files' user effects, each file recorded in `inputs`.
    pub fn load(&self, inputs: &Inputs) -> Result<Catalogue, CliError> {
        let mut catalogue = self.known.clone();
        catalogue
            .load_effect_files(&self.files, inputs)
            .map_err(CliError::input)?;
        Ok(catalogue)
    }
}

impl ModelArgs {
    /// The model the flags name; effect files read are recorded in `inputs`.
    pub fn model(&self, inputs: &Inputs) -> Result<Model, CliError> {
        Ok(self.model_and_catalogue(inputs)?.0)
    }

    /// The model the flags name and the effects the command knows (the
    /// compiled-in ones and the effect files' user effects, which a
    /// diagnosis may propose); effect files read are recorded in `inputs`.
    pub fn model_and_catalogue(&self, inputs: &Inputs) -> Result<(Model, Catalogue), CliError> {
        let catalogue = self.effect_files.load(inputs)?;
        Ok((self.model_in(&catalogue)?, catalogue))
    }

    /// The model the flags name, its effects looked up in `catalogue`.
    pub fn model_in(&self, catalogue: &Catalogue) -> Result<Model, CliError> {
        let name = self.preset.as_deref().unwrap_or("base");
        let mut model = preset(name).ok_or_else(|| {
            let known: Vec<&str> = PRESETS.iter().map(|p| p.0).collect();
            CliError::input(format!(
                "unknown preset `{}`{}; known presets: {}",
                crate::data::limits::echo(name),
                crate::effects::expr::suggest(name, known.iter().copied()),
                known.join(", ")
            ))
        })?;
        if let Some(c) = self.coefficients {
            model.coefficients = match c {
                CoefficientsArg::GrayHancock => CoefficientSet::GrayHancock,
                CoefficientsArg::Lighthill => CoefficientSet::Lighthill,
            };
        }
        for spec in &self.effects {
            let e = catalogue.parse_effect_spec(spec)?;
            if model.effects.iter().any(|m| m.name() == e.name()) {
                return Err(CliError::input(format!(
                    "effect `{}` is already in the model ({}); give it once",
                    e.name(),
                    model.describe()
                )));
            }
            model.effects.push(e);
        }
        let mut model = with_bases(model, catalogue)?;
        model.tail_method = match self.method {
            MethodArg::Exact => TailMethod::Exact,
            MethodArg::Quadrature => {
                // Per-case turns are checked by the data limits (<= MAX_TURNS).
                crate::data::limits::check_quadrature(
                    self.nodes_per_wavelength,
                    crate::data::limits::MAX_TURNS,
                )
                .map_err(|e| CliError::input(format!("--nodes-per-wavelength: {e}")))?;
                TailMethod::Quadrature {
                    nodes_per_wavelength: self.nodes_per_wavelength,
                }
            }
        };
        if !matches!(self.tail_model, TailModelArg::Rft) {
            if !(4..=200).contains(&self.segments_per_turn) {
                return Err(CliError::input(format!(
                    "--segments-per-turn must be between 4 and 200, got {}",
                    self.segments_per_turn
                )));
            }
            let spt = self.segments_per_turn;
            model.tail_method = match self.tail_model {
                TailModelArg::Sbt => TailMethod::SlenderBody {
                    segments_per_turn: spt,
                },
                _ => TailMethod::Stokeslets {
                    segments_per_turn: spt,
                },
            };
        }
        model.dofs = match self.dofs {
            DofsArg::Axial => Dofs::AXIAL,
            DofsArg::All => Dofs::ALL,
        };
        model.check_tail_compat().map_err(CliError::input)?;
        Ok(model)
    }
}

/// Add to `model` the effects its user effects were fitted on top of (their
/// `base` field, written by `diagnose --write-effect`) that it lacks, each
/// just before the effect that needs it, with a note on stderr; an effect
/// the model already has keeps the values it was given. A base that cannot
/// be applied is refused with what to add.
pub fn with_bases(mut model: Model, catalogue: &Catalogue) -> Result<Model, CliError> {
    let mut i = 0;
    while i < model.effects.len() {
        let effect = model.effects[i].effect.clone();
        let name = effect.name();
        let Some(user) = effect.as_formula() else {
            i += 1;
            continue;
        };
        let mut at = i;
        for spec in &user.spec().base {
            let e = catalogue.parse_effect_spec(spec).map_err(|err| {
                CliError::input(format!(
                    "effect `{name}`{} was fitted on top of `{spec}`, which cannot be applied: {err}; load the file that defines it with --effect-file, or remove it from the `base` field if you mean to use `{name}` alone",
                    source(user.source())
                ))
            })?;
            if model.effects.iter().any(|m| m.name() == e.name()) {
                continue;
            }
            eprintln!(
                "note: `{name}` was fitted on top of `{spec}`; added it to the model (give it with --effect to use other values)"
            );
            model.effects.insert(at, e);
            at += 1;
        }
        // An inserted base may have a base of its own: visit it next.
        if at == i {
            i += 1;
        }
    }
    Ok(model)
}

fn source(file: &str) -> String {
    if file.is_empty() {
        String::new()
    } else {
        format!(" (from {file})")
    }
}

/// `--data F`, shared by the subcommands that read measurements.
#[derive(Args, Debug, Clone)]
pub struct DataArgs {
    /// Dataset, TOML or CSV (docs/data-format.md) [default: the paper's built-in data].
    #[arg(long, value_name = "FILE")]
    pub data: Option<PathBuf>,
    /// The CSV writes numbers with a decimal comma (0,586) [default: detected from the cells].
    #[arg(long)]
    pub decimal_comma: bool,
    /// A study's data with the run sheets joined to it (never a flag):
    /// `data` names the study's dataset file, these are all its cases.
    #[arg(skip)]
    pub joined: Option<Dataset>,
}

impl DataArgs {
    /// The dataset, or the built-in paper data, recorded in `inputs`.
    pub fn load(&self, inputs: &Inputs) -> Result<Dataset, CliError> {
        if let Some(d) = &self.joined {
            return Ok(d.clone());
        }
        let options = data::ReadOptions {
            decimal_comma: self.decimal_comma,
        };
        load_data_with(&self.data, &options, inputs)
    }
}

/// Prefix a model failure with the dataset it came from, so that a message
/// like "case `x`: the force balance is singular" also names the file.
pub fn in_data(path: &Option<PathBuf>) -> impl Fn(crate::model::ModelError) -> CliError + '_ {
    move |e| {
        let file = path
            .as_ref()
            .map_or("<built-in paper data>".to_string(), |p| {
                p.display().to_string()
            });
        CliError::input(format!("{file}: {e}"))
    }
}

/// `path` or the built-in paper data, recorded in `inputs`.
pub fn load_data(path: &Option<PathBuf>, inputs: &Inputs) -> Result<Dataset, CliError> {
    load_data_with(path, &data::ReadOptions::default(), inputs)
}

/// [`load_data`] with what the user said of a CSV's dialect; what the
/// reader took as what (a spreadsheet's dialect, recorded columns) is
/// said once, on stderr.
pub fn load_data_with(
    path: &Option<PathBuf>,
    options: &data::ReadOptions,
    inputs: &Inputs,
) -> Result<Dataset, CliError> {
    match path {
        Some(p) => {
            let loaded = data::read_file(p, options, inputs)?;
            if let Some(note) = loaded.note {
                eprintln!("note: {note}");
            }
            Ok(loaded.dataset)
        }
        None => {
            inputs.record_named("<built-in paper data>", data::PAPER_TOML.as_bytes());
            Ok(data::paper())
        }
    }
}
