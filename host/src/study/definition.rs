//! What a step adds, written out in full in the study: the effect's name,
//! its physical statement, its reference, its formula in the paper's
//! notation, and for a user effect (a law `diagnose --write-effect` wrote,
//! or one of the user's own) the whole effects-file definition, so that the
//! study opens on any machine without the file it came from.

use crate::effects::formula::{to_toml, FormulaEffect};
use crate::effects::{user_file, Catalogue, Effect, EffectRef};
use crate::provenance::Inputs;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// A step's effect, as the study stores it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Definition {
    /// The effect's name (`swimbot effects` lists the catalogue's).
    pub name: String,
    /// `catalogue` (compiled in) or `user` (its definition below).
    pub kind: String,
    /// The physics in one line.
    pub statement: String,
    /// Where the physics comes from.
    pub reference: String,
    /// The law, `place = formula` per place, for a user effect; the
    /// catalogue effects state theirs in `statement`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub formula: Vec<String>,
    /// A user effect's definition as an effects file (docs/effects-format.md).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub definition: Option<String>,
}

/// The source label user effects from a study are registered under: the
/// same for every step, so that rebuilding a step's effect is one effect.
const SOURCE: &str = "a study's step";

impl Definition {
    /// A catalogue effect by name.
    pub fn of_catalogue(effect: &'static dyn Effect) -> Self {
        Definition {
            name: effect.name().to_string(),
            kind: "catalogue".into(),
            statement: effect.statement().to_string(),
            reference: effect.reference().to_string(),
            formula: Vec::new(),
            definition: None,
        }
    }

    /// A user effect read from an effects file: `NAME` chooses among
    /// several (one effect in the file needs none). The file is recorded
    /// in `inputs`.
    pub fn of_file(
        path: &Path,
        name: Option<&str>,
        inputs: &Inputs,
    ) -> Result<Self, DefinitionError> {
        let effects = user_file::load_file(path, inputs)?;
        let names = || effects.iter().map(|e| e.spec().name.clone()).collect();
        let chosen = match name {
            Some(n) => effects.iter().find(|e| e.spec().name == n).ok_or_else(|| {
                DefinitionError::NoSuchEffect {
                    file: path.to_path_buf(),
                    name: n.to_string(),
                    has: names(),
                }
            })?,
            None if effects.len() == 1 => &effects[0],
            None => {
                return Err(DefinitionError::WhichEffect {
                    file: path.to_path_buf(),
                    has: names(),
                })
            }
        };
        let mut spec = chosen.spec().clone();
        // What it was fitted on top of is the study's business now: the
        // step records the model beneath it.
        spec.base.clear();
        Ok(Definition {
            name: spec.name.clone(),
            kind: "user".into(),
            statement: spec.statement.clone(),
            reference: spec.reference.clone(),
            formula: spec
                .places
                .iter()
                .map(|(p, f)| format!("{} = {f}", p.name()))
                .collect(),
            definition: Some(to_toml(&[spec])),
        })
    }

    /// The effect it defines, looked up in `catalogue`; a user effect is
    /// registered in it first.
    pub fn effect(&self, catalogue: &mut Catalogue) -> Result<EffectRef, DefinitionError> {
        if let Some(text) = &self.definition {
            let specs = user_file::parse(text, SOURCE)?;
            let spec = specs
                .into_iter()
                .find(|s| s.name == self.name)
                .ok_or_else(|| DefinitionError::NotDefined(self.name.clone()))?;
            let effect =
                FormulaEffect::new(spec, SOURCE).map_err(|e| DefinitionError::Formula {
                    place: e.place.name().to_string(),
                    error: e.error,
                })?;
            catalogue.register_user_effects(vec![effect])?;
        }
        catalogue
            .by_name(&self.name)
            .ok_or_else(|| DefinitionError::Unknown(self.name.clone()))
    }
}

/// A step's effect that cannot be read or rebuilt: the file, the names
/// and the formula's place as data.
#[derive(Debug, thiserror::Error)]
pub enum DefinitionError {
    /// The effects file, or a stored definition, does not load.
    #[error("{0}")]
    File(#[from] user_file::UserEffectError),
    /// `FILE#NAME` names no effect of the file (`has`: its effects).
    #[error("{} has no effect `{name}`; it has: {}", .file.display(), .has.join(", "))]
    NoSuchEffect {
        file: std::path::PathBuf,
        name: String,
        has: Vec<String>,
    },
    /// A file of several effects without `#NAME`.
    #[error(
        "{} holds {} effects ({}); choose one with {}#NAME",
        .file.display(),
        .has.len(),
        .has.join(", "),
        .file.display()
    )]
    WhichEffect {
        file: std::path::PathBuf,
        has: Vec<String>,
    },
    #[error("the definition does not define `{0}`")]
    NotDefined(String),
    /// The stored formula at `place` does not compile.
    #[error("the formula at {place}: {error:?}")]
    Formula {
        place: String,
        error: crate::effects::expr::ExprError,
    },
    #[error("{0}")]
    Register(#[from] crate::effects::RegistryError),
    #[error("no effect `{0}` in this swimbot (`swimbot effects` lists them)")]
    Unknown(String),
}
