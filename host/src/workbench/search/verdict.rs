//! The found set put into the verdict of `diagnose`: the steps in
//! order, and (when the path goes beyond the single-step verdict) the kind,
//! the named catalogue effects, the located laws and the note
//! ([`crate::workbench::verdict::text::found_set_note`]); the verdict when one case
//! stands alone; and the located list without repeats. A set of two steps
//! or more carries what its joint fit fixes only together
//! ([`super::joint`]), in `verdict.joint` and the note; and the sets the
//! data cannot tell apart (`super::rivals`), listed.

use super::calibrate::Margin;
use super::joint_text::joint_sentences;
use super::level::Found;
use crate::data::Dataset;
use crate::format::fmt_sig;
use crate::workbench::diagnosis::{Baseline, Verdict, VerdictKind};
use crate::workbench::diagnosis::{DiagnoseSettings, ExplainingSet, SetsMargin};
use crate::workbench::discovery::Located;
use crate::workbench::experiments::separation::best_discriminating_case;
use crate::workbench::verdict::text::{fmt, verdict_of};

/// Put the path into the verdict: its steps always; when the path goes
/// beyond the single-step verdict (or is the first thing found), the kind,
/// the named effects, the located laws in order and the note; for a set of
/// two steps or more, what its joint fit fixes only together.
pub fn conclude(
    path: Found,
    v: &mut Verdict,
    base: &Baseline,
    data: &Dataset,
    s: &DiagnoseSettings,
) {
    v.steps = path.steps.iter().map(|p| p.0.clone()).collect();
    put_path(&path, v, base);
    put_rivals(&path, v, data, s.clear_margin);
    v.sets_margin = path
        .margin
        .filter(|_| !path.rivals.is_empty())
        .map(reported);
    let joint = super::joint::joint_reading(&path, data, s.likelihood);
    match joint {
        Ok(Some(j)) => {
            let said = joint_sentences(&j);
            if !said.is_empty() {
                v.note = format!("{}. Jointly: {}.", v.note, said.join("; "));
            }
            v.joint = Some(j);
        }
        Ok(None) => {}
        // The set stands as found; only what its parts fix is unknown.
        Err(e) => v.note = format!("{} (the steps could not be refitted jointly: {e})", v.note),
    }
}

/// The places (and catalogue names) of the found set, sorted.
fn places_of(path: &Found) -> Vec<String> {
    let mut v: Vec<String> = path
        .steps
        .iter()
        .map(|(step, _, l)| {
            l.as_ref()
                .map_or(step.name.clone(), |l| l.place.to_string())
        })
        .collect();
    v.sort();
    v
}

/// Several sets at different places that the data cannot tell apart
/// ([`super::rivals`]): the verdict is `indistinguishable`, lists each set
/// with its key difference and the measurement that would separate it from
/// the found set, and states as found only the places every set has.
fn put_rivals(path: &Found, v: &mut Verdict, data: &Dataset, margin: f64) {
    let Some((_, last, _)) = path.steps.last() else {
        return;
    };
    if path.rivals.is_empty() {
        return;
    }
    let found = places_of(path);
    let mut sets = vec![ExplainingSet {
        members: path.steps.iter().map(|p| p.0.name.clone()).collect(),
        places: found.clone(),
        key_difference: 0.0,
        at_noise_floor: last.at_floor,
        suggestion: None,
        akaike_weight: f64::NAN,
        model: Some(last.model.clone()),
    }];
    for r in &path.rivals {
        sets.push(ExplainingSet {
            members: r.members.clone(),
            places: r.places.clone(),
            key_difference: r.key_difference,
            at_noise_floor: r.at_floor,
            suggestion: best_discriminating_case(data, &last.model, &r.model),
            akaike_weight: f64::NAN,
            model: Some(r.model.clone()),
        });
    }
    put_akaike_weights(&mut sets);
    let agreed: Vec<String> = found
        .iter()
        .filter(|p| path.rivals.iter().all(|r| r.places.contains(p)))
        .cloned()
        .collect();
    let listed: Vec<String> = sets
        .iter()
        .enumerate()
        .map(|(i, s)| {
            let diff = match i {
                0 => "the set chosen: fewest members, then key".to_string(),
                _ => format!("key {:+.1}", s.key_difference),
            };
            format!("({}) {} [{diff}]", i + 1, s.members.join(" + "))
        })
        .collect();
    let agreed_said = match agreed.is_empty() {
        true => "the sets share no place: nothing is located for certain".to_string(),
        false => format!("every set has {}: that much is found", agreed.join(", ")),
    };
    let separations: Vec<String> = sets
        .iter()
        .enumerate()
        .skip(1)
        .filter_map(|(i, s)| Some((i, s.suggestion.as_ref()?)))
        .enumerate()
        .map(|(n, (i, g))| format!("set 1 against set {}{}", i + 1, g.hint_within(n > 0)))
        .collect();
    let floor = match last.at_floor {
        true => ", each at the noise floor",
        false => "",
    };
    let margin = match path.margin {
        Some(Margin {
            value,
            calibrated: Some(c),
        }) => {
            // A quantile of refit round-off (1e-12) is "never", not a number.
            let beaten = match c.quantile < 0.01 {
                true => "no wrong set beat it".to_string(),
                false => format!("a wrong set beat it by at most {}", fmt_sig(c.quantile, 3)),
            };
            format!(
                "{} ({} drawn from the chosen set's fit: 95 % of the time {beaten}; {} sets refitted on each)",
                fmt_sig(value, 3),
                c.draws,
                c.candidates
            )
        }
        Some(m) => fmt_sig(m.value, 3),
        None => fmt_sig(margin, 3),
    };
    v.note = format!(
        "indistinguishable on this data: {} sets of laws at different places explain it equally well (AICc + charges within {margin}{floor}): {}. {agreed_said}. {}. The first set in detail: {}",
        sets.len(),
        listed.join("; "),
        separations.join(". "),
        v.note
    );
    v.kind = VerdictKind::Indistinguishable;
    v.explained = last.at_floor;
    v.effect = None;
    v.indistinguishable = sets.iter().map(|s| s.members.join(" + ")).collect();
    v.suggestion = sets.get(1).and_then(|s| s.suggestion.clone());
    v.agreed_places = agreed;
    v.sets = sets;
}

/// The margin as `diagnose` reports it.
fn reported(m: Margin) -> SetsMargin {
    SetsMargin {
        value: m.value,
        bootstrap_quantile: m.calibrated.map(|c| c.quantile),
        draws: m.calibrated.map_or(0, |c| c.draws),
        candidates: m.calibrated.map_or(0, |c| c.candidates),
    }
}

fn put_path(path: &Found, v: &mut Verdict, base: &Baseline) {
    let Some(last) = path.steps.last().map(|p| &p.1) else {
        return;
    };
    if path.added == 0 && v.kind != VerdictKind::Unexplained {
        return;
    }
    let catalogue: Vec<&str> = path
        .steps
        .iter()
        .filter(|p| p.0.kind == "catalogue")
        .map(|p| p.0.name.as_str())
        .collect();
    let settled = last.at_floor || matches!(v.kind, VerdictKind::Located | VerdictKind::Identified);
    v.kind = match (settled, catalogue.is_empty()) {
        (false, _) => VerdictKind::Unexplained,
        (true, true) => VerdictKind::Located,
        (true, false) => VerdictKind::Identified,
    };
    v.explained = settled;
    // An unexplained verdict names no missing effect (its steps are partial).
    v.effect = (settled && !catalogue.is_empty()).then(|| catalogue.join(" + "));
    v.effect_explained_fraction = path
        .steps
        .iter()
        .find(|p| p.0.kind == "catalogue")
        .and_then(|p| p.0.explained_fraction);
    v.indistinguishable.clear();
    v.suggestion = None;
    v.located = path.steps.iter().filter_map(|p| p.2.clone()).collect();
    v.note = crate::workbench::verdict::text::found_set_note(base, path, last);
}

/// `none-needed` because bad runs or intervals stated too narrow account
/// for the whole excess ([`crate::workbench::data_quality`]); its sentences are put
/// in front of the note by the caller.
pub fn data_quality_verdict(base: &Baseline) -> Verdict {
    verdict_of(
        VerdictKind::NoneNeeded,
        format!(
            "none needed: no effect is needed beyond what the data's own quality explains (reduced chi-square {} on all quantities as judged, noise floor {})",
            fmt(base.chi2_reduced),
            fmt(base.noise_floor_chi2_reduced)
        ),
    )
}

/// Keep the first of laws with the same place, feature and form.
pub fn dedup_located(list: &mut Vec<Located>) {
    let mut seen: Vec<(
        &'static str,
        Option<std::borrow::Cow<'static, str>>,
        crate::effects::correction::Form,
    )> = Vec::new();
    list.retain(|l| {
        let key = (l.place, l.feature.clone(), l.form);
        let new = !seen.contains(&key);
        seen.push(key);
        new
    });
}

/// Each set's Akaike weight among `sets` from its key difference to the
/// found set. The key is AICc plus the search's charge, the same for every
/// set of a size, so the weights are Akaike weights of the stated sets.
fn put_akaike_weights(sets: &mut [ExplainingSet]) {
    let best = sets
        .iter()
        .map(|s| s.key_difference)
        .fold(f64::INFINITY, f64::min);
    let raw: Vec<f64> = sets
        .iter()
        .map(|s| (-(s.key_difference - best) / 2.0).exp())
        .collect();
    let total: f64 = raw.iter().sum();
    for (set, w) in sets.iter_mut().zip(raw) {
        set.akaike_weight = w / total;
    }
}
