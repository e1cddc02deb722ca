//! The effects known to this process: the compiled-in [`super::CATALOGUE`]
//! and the user effects loaded from effects files (`--effect-file FILE.toml`).
//!
//! User effects are registered once per process and never removed, which
//! is what lets them be `&'static dyn Effect` like the catalogue's.
//! Loading the same file twice is a no-op (several commands build their
//! model more than once); the same name from two places is an error.

use super::formula::FormulaEffect;
use super::user_file::{load_file, UserEffectError};
use super::{Effect, CATALOGUE};
use crate::provenance::Inputs;
use std::path::{Path, PathBuf};
use std::sync::RwLock;

static USER: RwLock<Vec<&'static FormulaEffect>> = RwLock::new(Vec::new());
static FILES: RwLock<Vec<PathBuf>> = RwLock::new(Vec::new());

/// Add user effects; a name already known (catalogue or user) is an error
/// unless it is the very same effect from the same source.
pub fn register_user_effects(
    effects: Vec<FormulaEffect>,
) -> Result<Vec<&'static FormulaEffect>, RegistryError> {
    let mut user = USER.write().unwrap_or_else(|e| e.into_inner());
    for (i, e) in effects.iter().enumerate() {
        let name = e.spec().name.as_str();
        if CATALOGUE.iter().any(|c| c.name() == name) {
            return Err(RegistryError::CatalogueName { name: name.into() });
        }
        if effects[..i].iter().any(|o| o.spec().name == name) {
            return Err(RegistryError::GivenTwice { name: name.into() });
        }
        if let Some(old) = user.iter().find(|o| o.spec().name == name) {
            if old.spec() != e.spec() || old.source() != e.source() {
                return Err(RegistryError::UserName {
                    name: name.into(),
                    from_file: e.source().to_string(),
                    registered_from: old.source().to_string(),
                });
            }
        }
    }
    let mut out = Vec::new();
    for e in effects {
        let existing = user
            .iter()
            .copied()
            .find(|o| o.spec().name == e.spec().name);
        let r = match existing {
            Some(old) => old,
            None => {
                let r = e.leak();
                user.push(r);
                r
            }
        };
        out.push(r);
    }
    Ok(out)
}

/// A user effect that cannot be registered: its name, and where the
/// effects of that name come from, as data.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum RegistryError {
    #[error("user effect `{name}` clashes with the catalogue effect of that name")]
    CatalogueName { name: String },
    #[error("user effect `{name}` is given twice")]
    GivenTwice { name: String },
    /// Another user effect of that name, registered from `registered_from`
    /// (empty: built in memory), differs from this one from `from_file`.
    #[error(
        "user effect `{name}`{} clashes with the user effect of that name{}",
        from(.from_file),
        from(.registered_from)
    )]
    UserName {
        name: String,
        from_file: String,
        registered_from: String,
    },
}

impl RegistryError {
    /// The name of the effect that cannot be registered.
    pub fn name(&self) -> &str {
        match self {
            RegistryError::CatalogueName { name }
            | RegistryError::GivenTwice { name }
            | RegistryError::UserName { name, .. } => name,
        }
    }
}

fn from(source: &str) -> String {
    if source.is_empty() {
        " (built in memory)".into()
    } else {
        format!(" from {source}")
    }
}

/// Load and register effects files, each recorded in `inputs`; a file
/// already loaded by this process is not registered again, but is still
/// read and recorded: it is an input of this command too.
pub fn load_effect_files(paths: &[PathBuf], inputs: &Inputs) -> Result<(), UserEffectError> {
    for path in paths {
        let key = path.canonicalize().unwrap_or_else(|_| path.clone());
        if FILES
            .read()
            .unwrap_or_else(|e| e.into_inner())
            .contains(&key)
        {
            record_again(path, inputs);
            continue;
        }
        let effects = load_file(path, inputs)?;
        let names: Vec<String> = effects.iter().map(|e| e.spec().name.clone()).collect();
        register_user_effects(effects).map_err(|e| clash(path, &names, &e))?;
        FILES.write().unwrap_or_else(|e| e.into_inner()).push(key);
    }
    Ok(())
}

/// Records a file registered by an earlier command as an input of this
/// one, with its bytes as they are now. A file that cannot be read any
/// more is left out: the effects in use are the ones registered.
fn record_again(path: &Path, inputs: &Inputs) {
    let limit = crate::data::limits::MAX_EFFECT_FILE_BYTES;
    if let Ok(text) = crate::input_file::read_text(path, limit, "an effects file") {
        inputs.record(path, text.as_bytes());
    }
}

/// A registration clash, placed at the clashing name's line in the file.
fn clash(path: &Path, names: &[String], e: &RegistryError) -> UserEffectError {
    let text =
        crate::input_file::read_text(path, crate::input_file::cap::EFFECTS, "an effects file")
            .unwrap_or_default();
    let name = names.iter().find(|n| n.as_str() == e.name());
    let line = name
        .and_then(|n| {
            text.lines()
                .position(|l| l.trim_start().starts_with("name") && l.contains(&format!("\"{n}\"")))
        })
        .map_or(0, |i| i + 1);
    UserEffectError {
        file: path.display().to_string(),
        effect: name.cloned(),
        field: "name".into(),
        line,
        column: 1,
        message: e.to_string(),
    }
}

/// The user effects registered so far, in loading order.
pub fn user_effects() -> Vec<&'static FormulaEffect> {
    USER.read().unwrap_or_else(|e| e.into_inner()).clone()
}

/// Every known effect: the catalogue, then the user effects.
pub fn all() -> Vec<&'static dyn Effect> {
    let mut v: Vec<&'static dyn Effect> = CATALOGUE.to_vec();
    v.extend(user_effects().into_iter().map(|e| e as &'static dyn Effect));
    v
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::effects::formula::UserEffectSpec;
    use crate::effects::place::Place;

    fn effect(name: &str, formula: &str, source: &str) -> FormulaEffect {
        let spec = UserEffectSpec {
            name: name.into(),
            statement: "s".into(),
            reference: "r".into(),
            applies_to: None,
            params: Vec::new(),
            places: vec![(Place::DriveRate, formula.into())],
            base: Vec::new(),
        };
        FormulaEffect::new(spec, source).unwrap()
    }

    #[test]
    fn the_same_effect_twice_is_one_effect_and_a_different_one_of_that_name_is_refused() {
        let a = register_user_effects(vec![effect("registry-test-a", "0.9", "a.toml")]).unwrap();
        let again =
            register_user_effects(vec![effect("registry-test-a", "0.9", "a.toml")]).unwrap();
        assert!(std::ptr::eq(a[0], again[0]));
        let err = register_user_effects(vec![effect("registry-test-a", "0.8", "b.toml")])
            .err()
            .unwrap()
            .to_string();
        assert!(err.contains("b.toml") && err.contains("a.toml"), "{err}");
        let err = register_user_effects(vec![effect("backflow", "0.8", "b.toml")])
            .err()
            .unwrap()
            .to_string();
        assert!(err.contains("catalogue"), "{err}");
        assert!(crate::effects::by_name("registry-test-a").is_some());
        assert!(all().iter().any(|e| e.name() == "registry-test-a"));
        assert_eq!(
            user_effects()
                .iter()
                .filter(|e| e.spec().name == "registry-test-a")
                .count(),
            1
        );
    }
}
