//! `diagnose`: which physical effect is the model missing?
//!
//! 1. The baseline: residuals in standard errors, summary errors, and the
//!    chi-square a perfect model would show ([`super::noise`]).
//! 2. Where it fails: residual trends against the quantity library
//!    ([`super::features`]).
//! 3. Every catalogue effect not yet in the model is added in turn, its
//!    free parameters fitted (weighted by the CIs), and scored by
//!    cross-validated MARE (leave-one-case-out up to ten cases, 10-fold
//!    above: leave-one-out refits grow with the square of the cases) and by
//!    AICc (`chi² + 2k + 2k(k+1)/(n-k-1)`, undefined when `n - k - 1 <= 0`).
//! 4. If no single effect reaches the noise floor, forward selection tries
//!    the best one with each other candidate.
//! 5. Discovery beyond the catalogue ([`super::discovery`]): a sparse search
//!    over (place, feature, form) locates the missing correction in the
//!    model's structure; when a catalogue effect explains most but not all
//!    of the excess, the remainder is located on top of it.
//! 6. The graded verdict ([`super::verdict`]): `none-needed`, `identified`,
//!    `located`, `indistinguishable` or `unexplained`, each named effect or
//!    correction with the share of the excess chi-square it removes.
//!
//! References: K. P. Burnham & D. R. Anderson, *Model Selection and
//! Multimodel Inference*, 2nd ed. (2002), ch. 2; C. M. Hurvich & C.-L. Tsai,
//! Biometrika 76 (1989) 297 (AICc); T. Hastie, R. Tibshirani & J. Friedman,
//! *The Elements of Statistical Learning*, 2nd ed. (2009), sec. 7.10.

use super::candidate::{evaluate, forward_selection, sort_by_aicc};
use super::compare::compare;
use super::features::trends;
use super::fit::FitError;
use super::noise::{chi2_noise_floor, error_dofs};
use crate::data::Dataset;
use crate::effects::EffectInstance;
use crate::model::Model;
use rayon::prelude::*;

pub use super::candidate::candidates;
pub use super::diagnosis::{
    Baseline, Candidate, DiagnoseSettings, Diagnosis, Remainder, SetMember, Verdict, VerdictKind,
};

/// Run the whole diagnosis of `model` on `data`.
pub fn diagnose(
    model: &Model,
    data: &Dataset,
    s: &DiagnoseSettings,
) -> Result<Diagnosis, FitError> {
    let say = |k: u64, m: &str| super::progress::say(&s.progress, k, m);
    // The data first: bad runs, intervals that look too narrow; what
    // follows is judged on the intervals trusted ([`super::data_quality`]).
    let (mut quality, widened) = super::data_quality::assess(model, data, s.level)?;
    let data = widened.as_ref().unwrap_or(data);
    // The model's own quantities (load torque, thrust, U, ...) join the
    // search's library: computed once here, one force balance per case,
    // and read by every law in them from then on.
    let attached = crate::model::columns::attach(model, data)?;
    let data = &attached;
    // Bad runs on several cases do not stop the search: a law may explain
    // them with their neighbours, and the two are weighed by one criterion
    // below ([`super::data_quality::weighed`]).
    let weigh_runs = s.discover && quality.runs_to_weigh();
    let searchable = !quality.explains_all() || weigh_runs;
    let cmp = compare(model, data, 0)?;
    let dofs = error_dofs(data);
    let n = cmp.summary.n;
    // The floor's quantile does not depend on k (only its (N-k)/N scaling):
    // one Monte Carlo run serves every candidate.
    let q0 = chi2_noise_floor(&dofs, 0, s.level);
    let floor = move |k: usize| q0.filter(|_| n > k).map(|q| q * (n - k) as f64 / n as f64);
    let floor0 = floor(0);
    let baseline = Baseline {
        model: model.describe(),
        mare: cmp.summary.mare,
        max_abs_rel_err: cmp.summary.max_abs_rel_err,
        chi2: cmp.summary.chi2,
        chi2_reduced: cmp.summary.chi2_reduced,
        noise_floor_chi2_reduced: floor0.map(|f| f / n as f64),
        at_noise_floor: floor0.is_some_and(|f| cmp.summary.chi2 <= f),
        t_deviance: super::robust::t_deviance_of(model, data)?,
    };
    let trends = trends(data, &cmp);
    let base_len = model.effects.len();
    say(2, "fitting the catalogue's effects");
    let cands = candidates(&s.catalogue, model, s.include_costly);
    // Warm the memoised non-local solves in parallel over cases (a
    // catalogue fit walks its cases serially; milliseconds per case).
    for e in &cands {
        let m = model
            .clone()
            .with_effect(EffectInstance::default_of(e.clone()));
        data.cases.par_iter().for_each(|c| {
            let _ = m.predict(c);
        });
    }
    let mut ranking: Vec<Candidate> = cands
        .par_iter()
        .filter_map(|e| {
            let m = model
                .clone()
                .with_effect(EffectInstance::default_of(e.clone()));
            evaluate(&m, &[base_len], data, &floor, s.likelihood).ok()
        })
        .collect();
    sort_by_aicc(&mut ranking);
    let pairs = if s.second_effect
        && !baseline.at_noise_floor
        && !ranking.iter().any(|c| c.score.at_noise_floor)
    {
        say(3, "forward selection: pairs of catalogue effects");
        forward_selection(model, data, &ranking, &floor, s.likelihood)
    } else {
        Vec::new()
    };
    let (mut discovery, mut remainder) = if s.discover && !baseline.at_noise_floor && searchable {
        say(4, "searching beyond the catalogue: place x feature x form");
        let reference = super::discovery::Reference {
            chi2: baseline.chi2,
            k: 0,
            floor: &floor,
            likelihood: s.likelihood,
        };
        let d = super::discovery::discover(model, data, &reference, &s.discovery)?;
        say(5, "locating what the best catalogue effects leave");
        let r = super::verdict::remainders(data, &baseline, &ranking, &d, &floor, s)?;
        (Some(d), r)
    } else {
        (None, None)
    };
    let mut verdict = match quality.explains_all() && !weigh_runs {
        true => super::search::verdict::data_quality_verdict(&baseline),
        false => {
            let evidence = super::verdict::Evidence {
                data,
                base: &baseline,
                ranking: &ranking,
                pairs: &pairs,
                discovery: discovery.as_ref(),
                remainder: remainder.as_ref(),
            };
            let mut v = super::verdict::verdict(&evidence, s);
            if s.discover {
                say(6, "searching over sets of laws, each refitted jointly");
                let path = super::search::search(model, &evidence, &v, &floor, s)?;
                let stability =
                    super::search::stability::stability(&path, model, data, s.search.resamples);
                super::search::verdict::conclude(path, &mut v, &baseline, data, s);
                v.stability = stability;
            }
            super::search::verdict::dedup_located(&mut v.located);
            // Only the laws the verdict keeps are profiled: a profile
            // costs tens of refits per parameter.
            v.located.par_iter_mut().for_each(|l| {
                l.profile = super::discovery::profiled(l, data, s.likelihood);
            });
            v
        }
    };
    if weigh_runs {
        let screened = discovery.as_ref().map_or(1, |d| d.screened);
        let charges = (
            2.0 * (screened.max(1) as f64).ln(),
            2.0 * (candidates(&s.catalogue, model, true).len().max(1) as f64).ln(),
        );
        if !quality.weigh(&verdict, n, charges) {
            // The runs explain the misfit better than any law: stated as
            // before, with nothing located.
            verdict = super::search::verdict::data_quality_verdict(&baseline);
            (discovery, remainder) = (None, None);
        }
    }
    super::data_quality::say_first(&quality, &mut verdict.note);
    if verdict.kind == VerdictKind::NoneNeeded {
        if let Some(unseen) = super::discovery::acts::unobservable_note(data) {
            continue_note(&mut verdict.note, &format!("; {unseen}"));
        }
    }
    if verdict.kind != VerdictKind::NoneNeeded {
        let found = verdict.located.first().map(|l| &l.model);
        let limits = super::experiments::design::limits_note(data, model, found);
        if !limits.is_empty() {
            continue_note(&mut verdict.note, &limits);
        }
    }
    Ok(Diagnosis {
        baseline,
        comparison: cmp,
        trends,
        ranking,
        pairs,
        discovery,
        remainder,
        data_quality: quality,
        verdict,
    })
}

/// The note's last sentence continued by `more` (its full stop dropped).
fn continue_note(note: &mut String, more: &str) {
    let kept = note.trim_end_matches('.').len();
    note.truncate(kept);
    note.push_str(more);
}
