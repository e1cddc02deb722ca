//! The graded verdict of `diagnose`: `none-needed`, `identified`,
//! `located`, `indistinguishable` or `unexplained`.
//!
//! Rules (each threshold is a documented guard, not a tuning):
//! - **none-needed**: the model is already at the noise floor.
//! - A finding is **supported** when it reaches the noise floor, its
//!   cross-validated MARE is below the baseline's MARE, and its chi-square
//!   drop beats `2k + 2 ln M` (`M` laws searched): the AIC penalty plus a
//!   Bonferroni-like charge for having looked at `M` laws, so that the best
//!   of several hundred fits is not read as physics by chance.
//! - A catalogue effect at the floor is preferred to a located correction
//!   (its physics is stated, not inferred) unless the correction beats it
//!   by the AICc margin: then **located**.
//! - With no catalogue effect at the floor, a catalogue effect that removes
//!   at least half of the excess and lowers MARE is kept, and what it
//!   leaves is located on top of it: **identified** with a remainder. It
//!   competes on AICc with a correction located alone.
//! - Two supported findings within the AICc margin that are not the same
//!   finding (same place, equivalent feature) are **indistinguishable**,
//!   with the new case that separates them best.
//! - Otherwise **unexplained**; only corrections that remove at least half
//!   of the excess and lower MARE are listed, as partial.
//!
//! Reference: Burnham & Anderson (2002), sec. 2.6 (AICc differences).

use super::design::best_discriminating_case;
use super::diagnosis::{Baseline, Candidate, DiagnoseSettings, Remainder, Verdict, VerdictKind};
use super::discovery::{discover, explained_fraction, Discovery, Located, Reference};
use super::fit::FitError;
use crate::data::Dataset;

/// Share of the excess a partial finding must remove to be shown.
const PARTIAL: f64 = 0.5;

use super::verdict_text::{fmt, frac, hint};

/// The finding to report from a discovery: among supported corrections
/// within the AICc margin of the best at the best's place, the one with the
/// fewest parameters (a near-constant law with a free exponent is not a
/// finding about its feature), ties by AICc.
fn parsimonious<'a>(
    d: &'a Discovery,
    base: &Baseline,
    margin: f64,
    data: &Dataset,
) -> Option<&'a Located> {
    // Choosing among the laws at one place is itself a search: charge it
    // like the whole search (2 ln of the laws per place).
    let margin = margin + 2.0 * ((d.screened.max(11) / 11) as f64).ln();
    let best = d
        .located
        .first()
        .filter(|l| supported(l, base, d.screened, data))?;
    d.located
        .iter()
        .filter(|l| {
            l.place == best.place
                && supported(l, base, d.screened, data)
                && aicc(l) - aicc(best) < margin
        })
        .min_by(|a, b| {
            a.params
                .len()
                .cmp(&b.params.len())
                .then(aicc(a).total_cmp(&aicc(b)))
        })
}

/// The MARE a perfect model shows out of sample: twice the expected
/// |relative error| of a normal variable, `2 sqrt(2/pi)` times the median
/// relative standard error (the factor 2 allows for five-trial SEs).
fn noise_mare(data: &Dataset) -> f64 {
    2.0 * super::design::median_rel_se(data) * (2.0 / std::f64::consts::PI).sqrt()
}

/// Whether a located correction is a finding: at the noise floor, or (an
/// approximate law) removing 95 % of the excess with a cross-validated
/// MARE at the noise level; its CV MARE below the baseline's; and its
/// chi-square drop above `2k + 2 ln M` (see the module docs).
fn supported(l: &Located, base: &Baseline, searched: usize, data: &Dataset) -> bool {
    let k = l.params.len() as f64;
    let approximate =
        l.explained_fraction.is_some_and(|f| f >= 0.95) && l.cv_mare <= noise_mare(data);
    let cost = 2.0 * k + 2.0 * (searched.max(1) as f64).ln();
    (l.at_noise_floor || approximate)
        && l.cv_mare < base.mare
        && base.chi2 - l.chi2 >= cost
        && base.t_deviance - l.t_deviance >= cost
}

fn partial(l: &Located, base: &Baseline) -> bool {
    l.explained_fraction.is_some_and(|f| f >= PARTIAL) && l.mare < base.mare
}

/// Locate what the best catalogue effects leave, when none reaches the
/// floor alone but some removes at least half of the excess (up to three
/// are tried; the one whose remainder fits best is kept).
pub fn remainders(
    data: &Dataset,
    base: &Baseline,
    ranking: &[Candidate],
    _alone: &Discovery,
    floor: &(dyn Fn(usize) -> Option<f64> + Sync),
    s: &DiagnoseSettings,
) -> Result<Option<Remainder>, FitError> {
    if ranking.iter().any(|c| c.at_noise_floor) {
        return Ok(None);
    }
    // Parsimony: a correction that reaches the floor alone leaves nothing a
    // combination could add at this data's precision.
    if parsimonious(_alone, base, s.clear_margin, data).is_some() {
        return Ok(None);
    }
    let floor0 = floor(0);
    let mut best: Option<Remainder> = None;
    let settings = super::discovery::DiscoverySettings {
        top: s.discovery.top.min(5),
        ..s.discovery.clone()
    };
    for c in ranking
        .iter()
        .filter(|c| {
            explained_fraction(base.chi2, c.chi2, floor0).is_some_and(|f| f >= PARTIAL)
                && c.mare < base.mare
        })
        .take(3)
    {
        let reference = Reference {
            chi2: c.chi2,
            k: c.params.len(),
            floor,
        };
        let d = discover(&c.model, data, &reference, &settings)?;
        let key = |d: &Discovery| {
            d.located
                .first()
                .and_then(|l| l.aicc)
                .unwrap_or(f64::INFINITY)
        };
        if best.as_ref().is_none_or(|b| key(&d) < key(&b.discovery)) {
            best = Some(Remainder {
                effect: c.effect.clone(),
                discovery: d,
            });
        }
    }
    Ok(best)
}

fn aicc(l: &Located) -> f64 {
    l.aicc.unwrap_or(f64::INFINITY)
}

/// Rivals of `best` among `pool`: supported, within the margin, and a
/// different finding (another place; or, when `best` scales with a
/// feature, a non-equivalent feature at the same place). A feature law at
/// the place of a constant `best` is not a rival: parsimony already chose
/// the constant. One rival per finding.
fn rivals<'a>(
    best: &Located,
    pool: &'a [Located],
    base: &Baseline,
    searched: usize,
    data: &Dataset,
    margin: f64,
) -> Vec<&'a Located> {
    let mut out: Vec<&Located> = Vec::new();
    for l in pool {
        let near = supported(l, base, searched, data) && aicc(l) - aicc(best) < margin;
        let same_place_simpler = l.place == best.place && best.feature.is_none();
        if near
            && !same_place_simpler
            && !best.same_finding(l, data)
            && !out.iter().any(|o| o.same_finding(l, data))
        {
            out.push(l);
        }
    }
    out
}

pub(crate) fn verdict_of(kind: VerdictKind, note: String) -> Verdict {
    Verdict {
        effect: None,
        explained: !matches!(kind, VerdictKind::Unexplained),
        kind,
        note,
        indistinguishable: Vec::new(),
        suggestion: None,
        effect_explained_fraction: None,
        located: Vec::new(),
        steps: Vec::new(),
    }
}

/// A supported finding, checked for rivals: located (or identified with a
/// remainder when `effect` is the catalogue effect beneath it).
fn finding(
    data: &Dataset,
    base: &Baseline,
    best: &Located,
    pool: &Discovery,
    effect: Option<&Candidate>,
    s: &DiagnoseSettings,
) -> Verdict {
    let rivals = rivals(
        best,
        &pool.located,
        base,
        pool.screened,
        data,
        s.clear_margin,
    );
    let floor0 = base.noise_floor_chi2_reduced.map(|r| r * base_n(base));
    let how = format!(
        "MARE {:.1} % -> {:.1} % (cross-validated {:.1} %), reduced chi-square {} -> {} (noise floor {})",
        100.0 * base.mare,
        100.0 * best.mare,
        100.0 * best.cv_mare,
        fmt(base.chi2_reduced),
        fmt(best.chi2_reduced),
        fmt(base.noise_floor_chi2_reduced)
    );
    if !rivals.is_empty() {
        let mut names = vec![best.describe()];
        names.extend(rivals.iter().map(|r| r.describe()));
        let suggestion = best_discriminating_case(data, &best.model, &rivals[0].model);
        let hint = suggestion.as_ref().map(hint).unwrap_or_default();
        let mut v = verdict_of(
            VerdictKind::Indistinguishable,
            format!(
                "indistinguishable on this data: {} fit equally well (AICc within {}){hint}",
                names.join("; "),
                s.clear_margin
            ),
        );
        v.indistinguishable = names;
        v.suggestion = suggestion;
        v.located = std::iter::once(best.clone())
            .chain(rivals.into_iter().cloned())
            .collect();
        if let Some(c) = effect {
            v.effect_explained_fraction = explained_fraction(base.chi2, c.chi2, floor0);
        }
        return v;
    }
    let mut v = match effect {
        Some(c) => {
            let f = explained_fraction(base.chi2, c.chi2, floor0);
            let mut v = verdict_of(
                VerdictKind::Identified,
                format!(
                    "missing: {} (removes {} of the excess chi-square) and, beyond it, located: {} ({}; removes {} of what {} leaves). {how}",
                    c.effect,
                    frac(f),
                    best.describe(),
                    best.interpretation,
                    frac(best.explained_fraction),
                    c.effect
                ),
            );
            v.effect = Some(c.effect.clone());
            v.effect_explained_fraction = f;
            v
        }
        None => verdict_of(
            VerdictKind::Located,
            format!(
                "no catalogue effect explains it; located: {} ({}; removes {} of the excess chi-square). {how}",
                best.describe(),
                best.interpretation,
                frac(best.explained_fraction)
            ),
        ),
    };
    v.located = vec![best.clone()];
    v
}

fn base_n(base: &Baseline) -> f64 {
    match (base.chi2_reduced, base.chi2) {
        (Some(r), c) if r > 0.0 => c / r,
        _ => f64::NAN,
    }
}

/// The verdict from the catalogue's ranking and pairs and the searches.
pub fn verdict(
    data: &Dataset,
    base: &Baseline,
    ranking: &[Candidate],
    pairs: &[Candidate],
    disc: Option<&Discovery>,
    rem: Option<&Remainder>,
    s: &DiagnoseSettings,
) -> Verdict {
    if base.at_noise_floor {
        return verdict_of(
            VerdictKind::NoneNeeded,
            format!(
                "none needed: the model already fits to the noise (reduced chi-square {} against a noise floor of {})",
                fmt(base.chi2_reduced),
                fmt(base.noise_floor_chi2_reduced)
            ),
        );
    }
    let floor0 = base.noise_floor_chi2_reduced.map(|r| r * base_n(base));
    let alone = disc.and_then(|d| parsimonious(d, base, s.clear_margin, data).map(|l| (l, d)));
    let pool: &[Candidate] = if ranking.iter().any(|c| c.at_noise_floor) || pairs.is_empty() {
        ranking
    } else {
        pairs
    };
    if let Some(cb) = pool.iter().find(|c| c.at_noise_floor) {
        if let Some((l, d)) = alone {
            // The located law is the best of `M` searched, the catalogue
            // effect one of a dozen stated in advance: the law must beat it
            // by the margin plus the search's charge 2 ln M.
            let charge = 2.0 * (d.screened.max(1) as f64).ln();
            if aicc(l) + s.clear_margin + charge <= cb.aicc.unwrap_or(f64::INFINITY) {
                let mut v = finding(data, base, l, d, None, s);
                v.note.push_str(&format!(
                    "; it beats the best catalogue effect at the floor, {}, by {:.1} in AICc",
                    cb.effect,
                    cb.aicc.unwrap_or(f64::NAN) - aicc(l)
                ));
                return v;
            }
        }
        let mut v = catalogue_verdict(data, base, pool, cb, floor0, s);
        if v.kind == VerdictKind::Identified {
            if let Some((l, _)) = alone {
                // A located law as good as the named effect: the same
                // physics if no nearby experiment separates them by 3
                // standard errors, else the data cannot tell them apart.
                // Only a law no more complex than the named effect competes
                // with it on equal terms; a richer one mimicking it within the
                // margin does not unseat stated physics.
                let k_cat = cb.params.len();
                if l.params.len() <= k_cat
                    && aicc(l) < cb.aicc.unwrap_or(f64::INFINITY) + s.clear_margin
                {
                    if let Some(g) = best_discriminating_case(data, &cb.model, &l.model)
                        .filter(|g| g.in_sigma >= 3.0)
                    {
                        v.kind = VerdictKind::Indistinguishable;
                        v.explained = true;
                        v.indistinguishable = vec![cb.effect.clone(), l.describe()];
                        v.note = format!(
                            "indistinguishable on this data: {} and the located {} ({}) fit equally well (AICc {:.1} against {:.1}); to tell them apart, measure {} with {} ({} differs by {:.0} %, about {:.0} standard errors)",
                            cb.effect,
                            l.describe(),
                            l.interpretation,
                            cb.aicc.unwrap_or(f64::NAN),
                            aicc(l),
                            g.base_case,
                            g.change,
                            g.quantity,
                            100.0 * g.rel_difference,
                            g.in_sigma
                        );
                        v.effect = None;
                        v.suggestion = Some(g);
                        v.located = vec![l.clone()];
                    }
                }
            }
        }
        return v;
    }
    let with_rem =
        rem.and_then(|r| parsimonious(&r.discovery, base, s.clear_margin, data).map(|l| (l, r)));
    match (alone, with_rem) {
        (Some((l, d)), Some((rl, _))) if aicc(l) < aicc(rl) + s.clear_margin => {
            finding(data, base, l, d, None, s)
        }
        (_, Some((rl, r))) => {
            let c = ranking.iter().find(|c| c.effect == r.effect);
            finding(data, base, rl, &r.discovery, c, s)
        }
        (Some((l, d)), None) => finding(data, base, l, d, None, s),
        (None, None) => unexplained(data, base, ranking, pairs, disc, rem, floor0, s),
    }
}

#[allow(clippy::too_many_arguments)]
fn unexplained(
    data: &Dataset,
    base: &Baseline,
    ranking: &[Candidate],
    pairs: &[Candidate],
    disc: Option<&Discovery>,
    rem: Option<&Remainder>,
    floor0: Option<f64>,
    s: &DiagnoseSettings,
) -> Verdict {
    let closest = ranking
        .iter()
        .find(|c| {
            c.mare < base.mare
                && explained_fraction(base.chi2, c.chi2, floor0).is_some_and(|f| f >= PARTIAL)
        })
        .map(|c| {
            format!(
                "; {} removes {} of the excess chi-square (MARE {:.1} % -> {:.1} %) but not all",
                c.effect,
                frac(explained_fraction(base.chi2, c.chi2, floor0)),
                100.0 * base.mare,
                100.0 * c.mare
            )
        })
        .unwrap_or_else(|| {
            "; no catalogue effect removes even half of the excess chi-square".into()
        });
    let mut located: Vec<Located> = disc
        .map(|d| {
            d.located
                .iter()
                .filter(|l| partial(l, base))
                .take(3)
                .cloned()
                .collect()
        })
        .unwrap_or_default();
    if let Some(r) = rem {
        if let Some(l) = r.discovery.located.first() {
            let mut l = l.clone();
            l.explained_fraction = explained_fraction(base.chi2, l.chi2, floor0);
            if partial(&l, base) {
                l.interpretation = format!("beyond {}: {}", r.effect, l.interpretation);
                located.push(l);
            }
        }
    }
    located.sort_by(|a, b| aicc(a).total_cmp(&aicc(b)));
    let partial_note = located
        .first()
        .map(|l| {
            format!(
                "; the best located correction, {}, removes {} ({}) but does not reach the floor",
                l.describe(),
                frac(l.explained_fraction),
                l.interpretation
            )
        })
        .unwrap_or_default();
    let mut v = verdict_of(
        VerdictKind::Unexplained,
        format!(
            "unexplained: no catalogue effect{}, and no located correction, brings the fit to the noise floor (reduced chi-square {}){closest}{partial_note}",
            if pairs.is_empty() { "" } else { " or pair" },
            fmt(base.noise_floor_chi2_reduced)
        ),
    );
    // Can this design tell the two best partial findings apart?
    if let Some(a) = located.first() {
        if let Some(b) = located[1..]
            .iter()
            .find(|b| !a.same_finding(b, data) && (aicc(b) - aicc(a)).abs() < s.clear_margin)
        {
            let g = best_discriminating_case(data, &a.model, &b.model);
            v.indistinguishable = vec![a.describe(), b.describe()];
            v.note.push_str(&format!(
                "; it and {} are indistinguishable on this design (AICc within {})",
                b.describe(),
                s.clear_margin
            ));
            if let Some(g) = &g {
                v.note.push_str(&hint(g));
            }
            v.suggestion = g;
        }
    }
    v.located = located;
    v
}

/// The catalogue's own verdict when some catalogue variant reaches the floor.
fn catalogue_verdict(
    data: &Dataset,
    base: &Baseline,
    pool: &[Candidate],
    best: &Candidate,
    floor0: Option<f64>,
    s: &DiagnoseSettings,
) -> Verdict {
    let best_aicc = best.aicc.unwrap_or(f64::INFINITY);
    let rivals: Vec<&Candidate> = pool
        .iter()
        .filter(|c| {
            c.effect != best.effect
                && c.at_noise_floor
                && c.cv_mare < base.mare
                && c.aicc.unwrap_or(f64::INFINITY) - best_aicc < s.clear_margin
        })
        .collect();
    let cv_falls = best.cv_mare < base.mare;
    let fraction = explained_fraction(base.chi2, best.chi2, floor0);
    if rivals.is_empty() && cv_falls {
        let mut v = verdict_of(
            VerdictKind::Identified,
            format!(
                "missing: {} (removes {} of the excess chi-square). MARE {:.1} % -> {:.1} % (cross-validated {:.1} %), reduced chi-square {} -> {} (noise floor {})",
                best.effect,
                frac(fraction),
                100.0 * base.mare,
                100.0 * best.mare,
                100.0 * best.cv_mare,
                fmt(base.chi2_reduced),
                fmt(best.chi2_reduced),
                fmt(base.noise_floor_chi2_reduced)
            ),
        );
        v.effect = Some(best.effect.clone());
        v.effect_explained_fraction = fraction;
        return v;
    }
    // A variant that does not beat the baseline out of sample is never
    // reported, whatever its rivals.
    if !cv_falls {
        return verdict_of(
            VerdictKind::NoneNeeded,
            format!(
                "none needed: the baseline's chi-square is above the noise floor (reduced {} against {}), but the best candidate, {}, does not lower the cross-validated error ({:.2} % against the baseline's {:.2} %): the excess is not an effect this data can support",
                fmt(base.chi2_reduced),
                fmt(base.noise_floor_chi2_reduced),
                best.effect,
                100.0 * best.cv_mare,
                100.0 * base.mare
            ),
        );
    }
    let suggestion = rivals
        .first()
        .and_then(|r| best_discriminating_case(data, &best.model, &r.model));
    let mut names: Vec<String> = vec![best.effect.clone()];
    names.extend(rivals.iter().map(|r| r.effect.clone()));
    let why = format!("they fit equally well (AICc within {})", s.clear_margin);
    let hint = suggestion.as_ref().map(hint).unwrap_or_default();
    let mut v = verdict_of(
        VerdictKind::Indistinguishable,
        format!(
            "indistinguishable on this data: {}: {why}{hint}",
            names.join(", ")
        ),
    );
    v.indistinguishable = names;
    v.suggestion = suggestion;
    v.effect_explained_fraction = fraction;
    v
}
