//! The answer of a diagnosis, as numbers: the verdict's kind, each step of
//! the found set as `place = law` with its parameters reported
//! ([`crate::workbench::fit::report`]), the error before and after (MARE,
//! the mean absolute relative error over U and Ω_b, and the reduced
//! chi-square against the noise floor), how sure (the sets' Akaike weights
//! and the terms' stability under resampling), the rivals and the next
//! step. The terminal prints it ([`super::render`]) and `diagnose --format
//! json` carries it as `headline`, so both say the same numbers; a study
//! keeps it with each diagnosis, and its page renders it.

use crate::data::quantities;
use crate::workbench::diagnose::{Diagnosis, VerdictKind};
use crate::workbench::diagnosis::{SetMember, TermStability};
use crate::workbench::discovery::Located;
use crate::workbench::fit::report::{ParamReport, StrongCorrelation};
use serde::{Deserialize, Serialize};
use std::borrow::Cow;

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Headline {
    /// The verdict's kind (`located`, `unexplained`, ...).
    pub kind: Cow<'static, str>,
    pub steps: Vec<HeadlineStep>,
    /// MARE (a fraction: 0.2107 is 21.07 %) of the base model, then after
    /// each step.
    pub mare: Vec<f64>,
    /// The reduced chi-square of the base model, then after each step
    /// (`null` where the data carry no uncertainties).
    #[serde(with = "nan_is_none")]
    pub chi2_reduced: Vec<Option<f64>>,
    /// The reduced chi-square a perfect model stays below.
    pub noise_floor_chi2_reduced: Option<f64>,
    pub at_noise_floor: bool,
    /// The rival sets (the found set first) with their Akaike weights.
    pub rivals: Vec<Rival>,
    /// How often resampled searches pick each term again (empty when it
    /// was not measured).
    pub stability: Vec<TermStability>,
    /// The measurement that best separates the rivals, in words.
    pub next_experiment: Option<String>,
    /// One command to run next.
    pub next_command: String,
}

/// One step of the found set.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct HeadlineStep {
    /// `catalogue` or `located`.
    pub kind: Cow<'static, str>,
    /// `place = law` (a located law) or the catalogue effect's name.
    pub law: String,
    /// The law's variable, normalised by its median over the cases.
    pub variable: Option<String>,
    /// The physical reading, one clause.
    pub reading: String,
    pub params: Vec<ParamReport>,
    /// Pairs of its parameters correlated beyond 0.8 (of the fit of the
    /// law's parameters; none in study files written before they were
    /// kept).
    #[serde(default)]
    pub correlations: Vec<StrongCorrelation>,
    /// Share of the excess chi-square left by the steps before that it
    /// removes (a fraction).
    pub explains: Option<f64>,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Rival {
    pub members: Vec<String>,
    pub key_difference: f64,
    pub akaike_weight: f64,
    pub at_noise_floor: bool,
}

/// The headline of `d`; `write_effect` is the file `--write-effect` wrote
/// (the next command then adds it to a study).
pub fn headline(d: &Diagnosis, write_effect: Option<&std::path::Path>) -> Headline {
    let v = &d.verdict;
    let b = &d.baseline;
    let mut steps: Vec<HeadlineStep> = Vec::new();
    let mut mare = vec![b.mare];
    let mut chi2_reduced = vec![b.chi2_reduced];
    let mut at_floor = b.at_noise_floor;
    let mut located = v.located.iter();
    if v.kind != VerdictKind::NoneNeeded {
        for (i, s) in v.steps.iter().enumerate() {
            let law = match s.kind {
                "located" => located.next(),
                _ => None,
            };
            steps.push(step(d, i, s, law));
            mare.push(s.mare);
            chi2_reduced.push(s.chi2_reduced);
            at_floor = s.at_noise_floor;
        }
        if v.steps.is_empty() {
            // A partial finding or a catalogue effect alone: its own fit.
            if let Some(l) = v.located.first() {
                steps.push(located_step(l));
                mare.push(l.score.mare);
                chi2_reduced.push(l.score.chi2_reduced);
                at_floor = l.score.at_noise_floor;
            } else if let Some(c) = v.effect.as_ref().and_then(|e| candidate(d, e)) {
                steps.push(catalogue_step(&c.effect, &c.params, None));
                mare.push(c.score.mare);
                chi2_reduced.push(c.score.chi2_reduced);
                at_floor = c.score.at_noise_floor;
            }
        }
    }
    let rivals = v
        .sets
        .iter()
        .map(|s| Rival {
            members: s.members.clone(),
            key_difference: s.key_difference,
            akaike_weight: s.akaike_weight,
            at_noise_floor: s.at_noise_floor,
        })
        .collect();
    let suggestion = v
        .suggestion
        .as_ref()
        .or_else(|| v.sets.iter().find_map(|s| s.suggestion.as_ref()));
    Headline {
        kind: v.kind.name().into(),
        steps,
        mare,
        chi2_reduced,
        noise_floor_chi2_reduced: b.noise_floor_chi2_reduced,
        at_noise_floor: at_floor,
        rivals,
        stability: v.stability.clone(),
        next_experiment: suggestion.map(|g| {
            g.hint()
                .trim_start_matches("; ")
                .trim_start_matches("to tell them apart, ")
                .to_string()
        }),
        next_command: next_command(d, write_effect),
    }
}

fn candidate<'a>(
    d: &'a Diagnosis,
    name: &str,
) -> Option<&'a crate::workbench::diagnose::Candidate> {
    d.ranking.iter().chain(&d.pairs).find(|c| c.effect == name)
}

/// Step `i` of the found set; a catalogue step below a located law shows
/// the joint values the law was fitted on (`on_top_of`), which have no
/// interval of their own.
fn step(d: &Diagnosis, i: usize, s: &SetMember, law: Option<&Located>) -> HeadlineStep {
    let mut st = match law {
        Some(l) => located_step(l),
        None => {
            let later = d.verdict.steps[i + 1..].iter().find_map(|t| {
                t.on_top_of
                    .iter()
                    .find(|e| e.split(':').next() == Some(&s.name))
            });
            match (later, candidate(d, &s.name)) {
                (Some(joint), _) => catalogue_step(&s.name, &[], Some(joint)),
                (None, Some(c)) => catalogue_step(&s.name, &c.params, None),
                (None, None) => catalogue_step(&s.name, &[], None),
            }
        }
    };
    st.explains = s.explained_fraction;
    st
}

fn catalogue_step(
    name: &str,
    params: &[crate::workbench::fit::Estimate],
    joint: Option<&String>,
) -> HeadlineStep {
    // A pair is named `a + b`.
    let catalogue = crate::effects::Catalogue::builtin();
    let reading = name
        .split(" + ")
        .filter_map(|n| catalogue.by_name(n).map(|e| e.statement().to_string()))
        .collect::<Vec<_>>()
        .join("; ");
    let params = match joint {
        // `NAME:k=v,...` at full precision.
        Some(j) => j
            .split_once(':')
            .map(|(_, kv)| {
                kv.split(',')
                    .filter_map(|p| p.split_once('='))
                    .filter_map(|(k, v)| Some(ParamReport::held(k, "", v.parse().ok()?)))
                    .collect()
            })
            .unwrap_or_default(),
        None => params.iter().map(|e| ParamReport::of(&e.name, e)).collect(),
    };
    HeadlineStep {
        kind: "catalogue".into(),
        law: name.to_string(),
        variable: None,
        reading,
        params,
        correlations: Vec::new(),
        explains: None,
    }
}

fn located_step(l: &Located) -> HeadlineStep {
    let (law, variable) = readable_law(l);
    HeadlineStep {
        kind: "located".into(),
        law: format!("{} = {law}", l.place),
        variable,
        reading: reading(&l.interpretation),
        params: l
            .params
            .iter()
            .enumerate()
            .map(|(i, e)| {
                let r = ParamReport::of(&e.name, e);
                match l.profile.as_ref().and_then(|p| p.intervals.get(i)) {
                    Some(p) => r.with_profile(p),
                    None => r,
                }
            })
            .collect(),
        correlations: l
            .profile
            .as_ref()
            .map(|p| p.correlations.clone())
            .unwrap_or_default(),
        explains: l.explained_fraction,
    }
}

/// The law with its feature written `x`, and what `x` is: the feature
/// relative to its median over the cases (the scale the search divides by,
/// `workbench/discovery/search.rs`).
fn readable_law(l: &Located) -> (String, Option<String>) {
    let Some(id) = l.feature.as_deref() else {
        return (l.formula.clone(), None);
    };
    let open = format!("({id} / ");
    let Some(at) = l.formula.find(&open) else {
        return (l.formula.clone(), None);
    };
    let rest = &l.formula[at + open.len()..];
    let Some(close) = rest.find(')') else {
        return (l.formula.clone(), None);
    };
    let median: Option<f64> = rest[..close].parse().ok();
    let law = format!("{}x{}", &l.formula[..at], &rest[close + 1..]);
    let q = quantities::by_id(id).or_else(|| {
        crate::data::model_quantities::MODEL_QUANTITIES
            .iter()
            .find(|q| q.id == id)
    });
    let what = q.map_or_else(
        || recorded_words(id),
        |q| {
            let symbol = q.name.split(" = ").next().unwrap_or(q.name);
            format!("{} {symbol}", q.doc)
        },
    );
    let unit = q.map_or("", |q| q.unit);
    let variable = match median {
        Some(m) => format!(
            "x = {what} relative to its median {}{}",
            crate::format::fmt_sig(m, 3),
            match unit {
                "" | "1" => String::new(),
                "deg" => "°".into(),
                u => format!(" {u}"),
            }
        ),
        None => format!("x = {what} over its median"),
    };
    (law, Some(variable))
}

/// `recorded.temperature_c` as "the recorded temperature_c".
fn recorded_words(id: &str) -> String {
    match id.strip_prefix(crate::data::feature::RECORDED_PREFIX) {
        Some(name) => format!("the recorded {name}"),
        None => id.to_string(),
    }
}

/// The interpretation's first clause, without the cases' range; the caveat
/// that a law lies outside what its place allows is kept.
fn reading(interpretation: &str) -> String {
    let first = interpretation.split("; ").next().unwrap_or(interpretation);
    let first = match first.find(" (from ") {
        Some(i) => &first[..i],
        None => first,
    };
    if interpretation.contains("so a fit, not an explanation") {
        format!("{first}; outside what this place allows, so a fit, not an explanation")
    } else {
        first.to_string()
    }
}

fn next_command(d: &Diagnosis, write_effect: Option<&std::path::Path>) -> String {
    let v = &d.verdict;
    if v.kind == VerdictKind::NoneNeeded {
        return "swimbot report".into();
    }
    if let Some(p) = write_effect {
        return format!("swimbot add {}", p.display());
    }
    let has_law = v.steps.iter().any(|s| s.kind == "located") || !v.located.is_empty();
    match (&v.effect, has_law) {
        (_, true) => "swimbot diagnose --write-effect found.toml".into(),
        (Some(e), false) => {
            let flags: Vec<String> = e.split(" + ").map(|n| format!("--effect {n}")).collect();
            format!("swimbot compare {}", flags.join(" "))
        }
        (None, false) => "swimbot diagnose --verbose".into(),
    }
}

/// A list of optional numbers as TOML can hold it (a TOML array has no
/// null): a missing one is written NaN, which JSON prints as `null`, and
/// read back as missing from either.
mod nan_is_none {
    use serde::{Deserialize, Deserializer, Serializer};

    pub fn serialize<S: Serializer>(v: &[Option<f64>], s: S) -> Result<S::Ok, S::Error> {
        s.collect_seq(v.iter().map(|x| x.unwrap_or(f64::NAN)))
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<Option<f64>>, D::Error> {
        let v = Vec::<Option<f64>>::deserialize(d)?;
        Ok(v.into_iter().map(|x| x.filter(|f| !f.is_nan())).collect())
    }
}
