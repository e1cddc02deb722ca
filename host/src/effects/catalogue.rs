//! The effects one command or one library call knows: the compiled-in
//! [`super::CATALOGUE`] and the user effects it loaded from effects files
//! (`--effect-file FILE.toml`), as a value passed to whatever looks an
//! effect up. Nothing is kept between calls: a second call sees only what
//! it loaded itself, and the effects go with the last model that holds
//! them. Loading the same file twice into one catalogue is a no-op
//! (several commands build their model more than once); the same name from
//! two places is an error.

use super::formula::FormulaEffect;
use super::spec::EffectSpecError;
use super::user_file::{load_file, UserEffectError};
use super::{Effect, EffectInstance, EffectRef, CATALOGUE};
use crate::provenance::Inputs;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// The built-in effects and the user effects loaded so far, in loading order.
#[derive(Clone, Default)]
pub struct Catalogue {
    user: Vec<Arc<FormulaEffect>>,
    /// The effects files loaded, canonicalised.
    files: Vec<PathBuf>,
}

impl std::fmt::Debug for Catalogue {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let names: Vec<&str> = self.user.iter().map(|e| e.name()).collect();
        f.debug_struct("Catalogue").field("user", &names).finish()
    }
}

impl Catalogue {
    /// The compiled-in effects only.
    pub fn builtin() -> Self {
        Catalogue::default()
    }

    /// Add user effects; a name already known (catalogue or user) is an
    /// error unless it is the very same effect from the same source.
    pub fn register_user_effects(
        &mut self,
        effects: Vec<FormulaEffect>,
    ) -> Result<Vec<Arc<FormulaEffect>>, RegistryError> {
        for (i, e) in effects.iter().enumerate() {
            let name = e.spec().name.as_str();
            if CATALOGUE.iter().any(|c| c.name() == name) {
                return Err(RegistryError::CatalogueName { name: name.into() });
            }
            if effects[..i].iter().any(|o| o.spec().name == name) {
                return Err(RegistryError::GivenTwice { name: name.into() });
            }
            if let Some(old) = self.user.iter().find(|o| o.spec().name == name) {
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
            let existing = self.user.iter().find(|o| o.spec().name == e.spec().name);
            let r = match existing {
                Some(old) => old.clone(),
                None => {
                    let r = Arc::new(e);
                    self.user.push(r.clone());
                    r
                }
            };
            out.push(r);
        }
        Ok(out)
    }

    /// Load and register effects files, each recorded in `inputs`; a file
    /// this catalogue already loaded is not registered again, but is still
    /// read and recorded: it is an input of this command too.
    pub fn load_effect_files(
        &mut self,
        paths: &[PathBuf],
        inputs: &Inputs,
    ) -> Result<(), UserEffectError> {
        for path in paths {
            let key = path.canonicalize().unwrap_or_else(|_| path.clone());
            if self.files.contains(&key) {
                record_again(path, inputs);
                continue;
            }
            let effects = load_file(path, inputs)?;
            let names: Vec<String> = effects.iter().map(|e| e.spec().name.clone()).collect();
            self.register_user_effects(effects)
                .map_err(|e| clash(path, &names, &e))?;
            self.files.push(key);
        }
        Ok(())
    }

    /// The user effects, in loading order.
    pub fn user_effects(&self) -> &[Arc<FormulaEffect>] {
        &self.user
    }

    /// Every known effect: the compiled-in ones, then the user effects.
    pub fn all(&self) -> Vec<EffectRef> {
        let mut v: Vec<EffectRef> = CATALOGUE.iter().map(|e| EffectRef::from(*e)).collect();
        v.extend(self.user.iter().map(|e| EffectRef::from(e.clone())));
        v
    }

    /// Look an effect (compiled-in or user) up by its command-line name.
    pub fn by_name(&self, name: &str) -> Option<EffectRef> {
        if let Some(e) = CATALOGUE.iter().find(|e| e.name() == name) {
            return Some(EffectRef::from(*e));
        }
        self.user
            .iter()
            .find(|e| e.name() == name)
            .map(|e| EffectRef::from(e.clone()))
    }

    /// Parse one `NAME[:k=v,...]` against this catalogue.
    pub fn parse_effect_spec(&self, text: &str) -> Result<EffectInstance, EffectSpecError> {
        super::spec::parse_in(self, text)
    }

    /// Parse `A + B:k=v + C` against this catalogue.
    pub fn parse_effect_list(&self, text: &str) -> Result<Vec<EffectInstance>, EffectSpecError> {
        super::spec::parse_list_in(self, text)
    }
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

/// Records a file loaded before by this catalogue as an input of this
/// command, with its bytes as they are now. A file that cannot be read any
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
        let mut cat = Catalogue::builtin();
        let a = cat
            .register_user_effects(vec![effect("registry-test-a", "0.9", "a.toml")])
            .unwrap();
        let again = cat
            .register_user_effects(vec![effect("registry-test-a", "0.9", "a.toml")])
            .unwrap();
        assert!(Arc::ptr_eq(&a[0], &again[0]));
        let err = cat
            .register_user_effects(vec![effect("registry-test-a", "0.8", "b.toml")])
            .err()
            .unwrap()
            .to_string();
        assert!(err.contains("b.toml") && err.contains("a.toml"), "{err}");
        let err = cat
            .register_user_effects(vec![effect("backflow", "0.8", "b.toml")])
            .err()
            .unwrap()
            .to_string();
        assert!(err.contains("catalogue"), "{err}");
        assert!(cat.by_name("registry-test-a").is_some());
        assert!(cat.all().iter().any(|e| e.name() == "registry-test-a"));
        assert_eq!(
            cat.user_effects()
                .iter()
                .filter(|e| e.spec().name == "registry-test-a")
                .count(),
            1
        );
    }

    #[test]
    fn a_catalogue_knows_only_what_it_loaded() {
        let mut first = Catalogue::builtin();
        first
            .register_user_effects(vec![effect("registry-test-b", "0.9", "a.toml")])
            .unwrap();
        let second = Catalogue::builtin();
        assert!(first.by_name("registry-test-b").is_some());
        assert!(second.by_name("registry-test-b").is_none());
        assert!(second.by_name("backflow").is_some());
    }
}
