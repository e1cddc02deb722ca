//! Parsing effect specifications from the command line:
//! `NAME` or `NAME:param=value,param=value`, and `+`-joined lists of them.

use super::{Catalogue, EffectInstance};

#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum EffectSpecError {
    #[error("unknown effect `{name}`{suggestion}; known effects: {known} (a user effect needs --effect-file FILE.toml before it can be named)")]
    UnknownEffect {
        name: String,
        /// " (did you mean `x`?)" or nothing.
        suggestion: String,
        known: String,
    },
    #[error("effect `{effect}` has no parameter `{param}`; its parameters: {known}")]
    UnknownParam {
        effect: String,
        param: String,
        known: String,
    },
    #[error("effect `{effect}`, parameter `{param}`: `{value}` is not a number")]
    NotANumber {
        effect: String,
        param: String,
        value: String,
    },
    /// `unit` is empty for a dimensionless parameter, else " mm" etc.
    #[error("effect `{effect}`, parameter `{param}` = {value} is outside its bounds [{min}, {max}]{unit}")]
    OutOfBounds {
        effect: String,
        param: String,
        value: f64,
        min: f64,
        max: f64,
        unit: String,
    },
    #[error("effect `{effect}`: `{item}` is not of the form param=value")]
    Malformed { effect: String, item: String },
    #[error("effect `{effect}`: {problem}")]
    Repeated { effect: String, problem: String },
}

/// Parse one `NAME[:k=v,...]` naming a compiled-in effect; a user effect
/// is parsed by the [`Catalogue`] that loaded it.
pub fn parse_effect_spec(text: &str) -> Result<EffectInstance, EffectSpecError> {
    parse_in(&Catalogue::builtin(), text)
}

/// Parse one `NAME[:k=v,...]` against `catalogue`.
pub(super) fn parse_in(
    catalogue: &Catalogue,
    text: &str,
) -> Result<EffectInstance, EffectSpecError> {
    let (name, params) = match text.split_once(':') {
        Some((n, p)) => (n.trim(), Some(p)),
        None => (text.trim(), None),
    };
    let all = catalogue.all();
    let effect = catalogue
        .by_name(name)
        .ok_or_else(|| EffectSpecError::UnknownEffect {
            name: crate::data::limits::echo(name),
            suggestion: super::expr::suggest(name, all.iter().map(|e| e.name())),
            known: all.iter().map(|e| e.name()).collect::<Vec<_>>().join(", "),
        })?;
    let mut inst = EffectInstance::default_of(effect.clone());
    if params.is_some_and(|p| p.trim().is_empty()) {
        return Err(EffectSpecError::Malformed {
            effect: name.to_string(),
            item: "(nothing after the colon)".to_string(),
        });
    }
    let mut given = vec![false; effect.params().len()];
    for item in params
        .into_iter()
        .flat_map(|p| p.split(','))
        .filter(|s| !s.trim().is_empty())
    {
        let (k, v) = item
            .split_once('=')
            .ok_or_else(|| EffectSpecError::Malformed {
                effect: name.to_string(),
                item: item.to_string(),
            })?;
        let (k, v) = (k.trim(), v.trim());
        let specs = effect.params();
        let idx = specs.iter().position(|p| p.name == k).ok_or_else(|| {
            EffectSpecError::UnknownParam {
                effect: name.to_string(),
                param: k.to_string(),
                known: if specs.is_empty() {
                    "none".to_string()
                } else {
                    specs
                        .iter()
                        .map(|p| p.name.as_ref())
                        .collect::<Vec<_>>()
                        .join(", ")
                },
            }
        })?;
        let value: f64 = v
            .parse()
            .ok()
            .filter(|x: &f64| x.is_finite())
            .ok_or_else(|| EffectSpecError::NotANumber {
                effect: name.to_string(),
                param: k.to_string(),
                value: v.to_string(),
            })?;
        let p = &specs[idx];
        if value < p.min || value > p.max {
            return Err(EffectSpecError::OutOfBounds {
                effect: name.to_string(),
                param: k.to_string(),
                value,
                min: p.min,
                max: p.max,
                unit: match p.unit.as_ref() {
                    "" | "1" => String::new(),
                    u => format!(" {u}"),
                },
            });
        }
        if std::mem::replace(&mut given[idx], true) {
            return Err(EffectSpecError::Repeated {
                effect: name.to_string(),
                problem: format!("parameter `{k}` is given twice"),
            });
        }
        inst.values[idx] = value;
    }
    Ok(inst)
}

/// Parse `A + B:k=v + C` (used by `synth --truth`) naming compiled-in effects.
pub fn parse_effect_list(text: &str) -> Result<Vec<EffectInstance>, EffectSpecError> {
    parse_list_in(&Catalogue::builtin(), text)
}

/// Parse `A + B:k=v + C` against `catalogue`.
pub(super) fn parse_list_in(
    catalogue: &Catalogue,
    text: &str,
) -> Result<Vec<EffectInstance>, EffectSpecError> {
    text.split('+')
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .map(|s| parse_in(catalogue, s))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_names_and_parameters() {
        let e = parse_effect_spec("body-correction:translation=16,rotation=1.4").unwrap();
        assert_eq!(e.values, vec![16.0, 1.4]);
        assert!(parse_effect_spec("backflow").unwrap().values.is_empty());
    }

    #[test]
    fn rejects_with_a_message_that_names_the_problem() {
        let e = parse_effect_spec("bogus").unwrap_err().to_string();
        assert!(e.contains("bogus") && e.contains("backflow"), "{e}");
        let e = parse_effect_spec("body-correction:speed=3")
            .unwrap_err()
            .to_string();
        assert!(e.contains("speed") && e.contains("translation"), "{e}");
        let e = parse_effect_spec("body-correction:translation=abc")
            .unwrap_err()
            .to_string();
        assert!(e.contains("abc"), "{e}");
        let e = parse_effect_spec("body-correction:translation=-1")
            .unwrap_err()
            .to_string();
        assert!(e.contains("outside"), "{e}");
        let e = parse_effect_spec("body-correction:translation=NaN")
            .unwrap_err()
            .to_string();
        assert!(e.contains("not a number"), "{e}");
    }
}
