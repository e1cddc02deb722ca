//! The graded verdict of `diagnose`, as a decision: `none-needed`,
//! `identified`, `located`, `indistinguishable` or `unexplained`, with the
//! candidates and laws it rests on. How each decision is worded is in
//! [`self::text`].
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
//!   competes on AICc with a correction located alone; when only a
//!   catalogue *pair* reaches the floor, the catalogue effect with the law
//!   on top of it must beat the pair by the margin plus the search's charge
//!   `2 ln M`, as a law alone must beat a catalogue effect (else a free
//!   trim can stand in for a tail drag near the wall).
//! - Two supported findings within the AICc margin that are not the same
//!   finding (same place, equivalent feature) are **indistinguishable**,
//!   with the new case that separates them best.
//! - Otherwise **unexplained**; only corrections that remove at least half
//!   of the excess and lower MARE are listed, as partial.
//!
//! Reference: Burnham & Anderson (2002), sec. 2.6 (AICc differences).

pub mod rules;
pub mod text;

use super::diagnosis::{Baseline, Candidate, DiagnoseSettings, Remainder, Verdict};
use super::discovery::{discover, explained_fraction, Discovery, Located, Reference};
use super::experiments::separation::{best_discriminating_case, Suggestion};
use super::fit::FitError;
use crate::data::Dataset;

pub use self::rules::{aicc, parsimonious, partial, PARTIAL};

/// What the verdict is decided from: the data, the baseline, the
/// catalogue's ranking and pairs, and the searches beyond it. Shared by
/// [`verdict`] and [`super::search::search`].
#[derive(Clone, Copy)]
pub struct Evidence<'a> {
    pub data: &'a Dataset,
    pub base: &'a Baseline,
    pub ranking: &'a [Candidate],
    pub pairs: &'a [Candidate],
    pub discovery: Option<&'a Discovery>,
    pub remainder: Option<&'a Remainder>,
}

/// What was decided, before it is worded.
pub enum Decision<'a> {
    /// The model is at the noise floor.
    AtFloor,
    /// The best catalogue effect reaches the floor but does not lower the
    /// cross-validated error.
    NotOutOfSample { best: &'a Candidate },
    /// One catalogue effect at the floor, no rival.
    Catalogue {
        best: &'a Candidate,
        fraction: Option<f64>,
    },
    /// Catalogue effects at the floor within the margin of each other.
    CatalogueRivals {
        names: Vec<String>,
        suggestion: Option<Suggestion>,
        fraction: Option<f64>,
    },
    /// A catalogue effect and a law as simple that fit equally well, and a
    /// nearby case that separates them.
    CatalogueOrLaw {
        effect: &'a Candidate,
        law: &'a Located,
        suggestion: Suggestion,
    },
    /// A supported law, alone or on top of a catalogue effect; `beats` is
    /// the catalogue effect at the floor it beats, with the AICc margin.
    Law {
        law: &'a Located,
        beneath: Option<(&'a Candidate, Option<f64>)>,
        beats: Option<(&'a Candidate, f64)>,
    },
    /// Supported laws within the margin that are different findings.
    LawRivals {
        laws: Vec<&'a Located>,
        suggestion: Option<Suggestion>,
        beneath_fraction: Option<f64>,
    },
    /// Nothing reaches the floor: the closest catalogue effect (removing at
    /// least half), the partial laws (best first) and, when the two best
    /// partial laws are within the margin, the case that separates them.
    Unexplained {
        closest: Option<(&'a Candidate, Option<f64>)>,
        partial: Vec<Located>,
        rival: Option<(String, String, Option<Suggestion>)>,
    },
}

/// The excess chi-square's floor on all quantities.
pub(crate) fn floor0(base: &Baseline) -> Option<f64> {
    let n = match (base.chi2_reduced, base.chi2) {
        (Some(r), c) if r > 0.0 => c / r,
        _ => f64::NAN,
    };
    base.noise_floor_chi2_reduced.map(|r| r * n)
}

/// Locate what the best catalogue effects leave, when none reaches the
/// floor alone but some removes at least half of the excess (up to three
/// are tried; the one whose remainder fits best is kept).
pub fn remainders(
    data: &Dataset,
    base: &Baseline,
    ranking: &[Candidate],
    alone: &Discovery,
    floor: &(dyn Fn(usize) -> Option<f64> + Sync),
    s: &DiagnoseSettings,
) -> Result<Option<Remainder>, FitError> {
    if ranking.iter().any(|c| c.score.at_noise_floor) {
        return Ok(None);
    }
    // Parsimony: a correction that reaches the floor alone leaves nothing a
    // combination could add at this data's precision.
    if parsimonious(alone, base, s.clear_margin, data).is_some() {
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
            explained_fraction(base.chi2, c.score.chi2, floor0).is_some_and(|f| f >= PARTIAL)
                && c.score.mare < base.mare
        })
        .take(3)
    {
        let reference = Reference {
            chi2: c.score.chi2,
            k: c.params.len(),
            floor,
            likelihood: s.likelihood,
        };
        let d = discover(&c.model, data, &reference, &settings)?;
        let key = |d: &Discovery| d.located.first().map_or(f64::INFINITY, aicc);
        if best.as_ref().is_none_or(|b| key(&d) < key(&b.discovery)) {
            best = Some(Remainder {
                effect: c.effect.clone(),
                discovery: d,
            });
        }
    }
    Ok(best)
}

/// The verdict from the evidence (decided by [`decide`], worded by
/// [`self::text::word`]).
pub fn verdict(e: &Evidence, s: &DiagnoseSettings) -> Verdict {
    self::text::word(decide(e, s), e, s)
}

/// The decision (module docs).
pub fn decide<'a>(e: &Evidence<'a>, s: &DiagnoseSettings) -> Decision<'a> {
    let (data, base) = (e.data, e.base);
    if base.at_noise_floor {
        return Decision::AtFloor;
    }
    let alone = e
        .discovery
        .and_then(|d| parsimonious(d, base, s.clear_margin, data).map(|l| (l, d)));
    let pool: &[Candidate] =
        if e.ranking.iter().any(|c| c.score.at_noise_floor) || e.pairs.is_empty() {
            e.ranking
        } else {
            e.pairs
        };
    if let Some(cb) = pool.iter().find(|c| c.score.at_noise_floor) {
        if let Some((l, d)) = alone {
            // The located law is the best of `M` searched, the catalogue
            // effect one of a dozen stated in advance: the law must beat it
            // by the margin plus the search's charge 2 ln M.
            let charge = 2.0 * (d.screened.max(1) as f64).ln();
            let cat = cb.score.aicc.unwrap_or(f64::INFINITY);
            if aicc(l) + s.clear_margin + charge <= cat {
                return finding(e, l, d, None, Some((cb, cat - aicc(l))), s);
            }
        }
        // A catalogue pair at the floor against the best catalogue effect
        // with the law located on top of it (else a free trim can stand in
        // for a tail drag near the wall): the law pays the same charge.
        if let Some((rl, r)) = e
            .remainder
            .and_then(|r| parsimonious(&r.discovery, base, s.clear_margin, data).map(|l| (l, r)))
        {
            let charge = 2.0 * (r.discovery.screened.max(1) as f64).ln();
            let cat = cb.score.aicc.unwrap_or(f64::INFINITY);
            if aicc(rl) + s.clear_margin + charge <= cat {
                let c = e.ranking.iter().find(|c| c.effect == r.effect);
                return finding(e, rl, &r.discovery, c, Some((cb, cat - aicc(rl))), s);
            }
        }
        let decided = catalogue(e, pool, cb, s);
        if let (Decision::Catalogue { .. }, Some((l, _))) = (&decided, alone) {
            if let Some(g) = same_as_catalogue(data, cb, l, s) {
                return Decision::CatalogueOrLaw {
                    effect: cb,
                    law: l,
                    suggestion: g,
                };
            }
        }
        return decided;
    }
    let with_rem = e
        .remainder
        .and_then(|r| parsimonious(&r.discovery, base, s.clear_margin, data).map(|l| (l, r)));
    match (alone, with_rem) {
        (Some((l, d)), Some((rl, _))) if aicc(l) < aicc(rl) + s.clear_margin => {
            finding(e, l, d, None, None, s)
        }
        (_, Some((rl, r))) => {
            let c = e.ranking.iter().find(|c| c.effect == r.effect);
            finding(e, rl, &r.discovery, c, None, s)
        }
        (Some((l, d)), None) => finding(e, l, d, None, None, s),
        (None, None) => unexplained(e, s),
    }
}

/// A located law as good as the named effect: the same physics if no
/// nearby experiment separates them by 3 standard errors, else the data
/// cannot tell them apart. Only a law no more complex than the named
/// effect competes with it on equal terms; a richer one mimicking it within
/// the margin does not unseat stated physics.
fn same_as_catalogue(
    data: &Dataset,
    cb: &Candidate,
    l: &Located,
    s: &DiagnoseSettings,
) -> Option<Suggestion> {
    let close = l.params.len() <= cb.params.len()
        && aicc(l) < cb.score.aicc.unwrap_or(f64::INFINITY) + s.clear_margin;
    if !close {
        return None;
    }
    best_discriminating_case(data, &cb.model, &l.model).filter(|g| g.in_sigma >= 3.0)
}

/// A supported finding, checked for rivals: a law alone or on top of the
/// catalogue effect `effect`.
fn finding<'a>(
    e: &Evidence<'a>,
    best: &'a Located,
    pool: &'a Discovery,
    effect: Option<&'a Candidate>,
    beats: Option<(&'a Candidate, f64)>,
    s: &DiagnoseSettings,
) -> Decision<'a> {
    let rivals = self::rules::rivals(
        best,
        &pool.located,
        e.base,
        pool.screened,
        e.data,
        s.clear_margin,
    );
    let floor0 = floor0(e.base);
    let beneath = effect.map(|c| (c, explained_fraction(e.base.chi2, c.score.chi2, floor0)));
    if rivals.is_empty() {
        return Decision::Law {
            law: best,
            beneath,
            beats,
        };
    }
    let suggestion = best_discriminating_case(e.data, &best.model, &rivals[0].model);
    Decision::LawRivals {
        laws: std::iter::once(best).chain(rivals).collect(),
        suggestion,
        beneath_fraction: beneath.and_then(|b| b.1),
    }
}

fn unexplained<'a>(e: &Evidence<'a>, s: &DiagnoseSettings) -> Decision<'a> {
    let (base, data) = (e.base, e.data);
    let floor0 = floor0(base);
    let closest = e
        .ranking
        .iter()
        .map(|c| (c, explained_fraction(base.chi2, c.score.chi2, floor0)))
        .find(|(c, f)| c.score.mare < base.mare && f.is_some_and(|f| f >= PARTIAL));
    let mut located: Vec<Located> = e
        .discovery
        .map(|d| {
            d.located
                .iter()
                .filter(|l| partial(l, base))
                .take(3)
                .cloned()
                .collect()
        })
        .unwrap_or_default();
    if let Some(r) = e.remainder {
        if let Some(l) = r.discovery.located.first() {
            let mut l = l.clone();
            l.explained_fraction = explained_fraction(base.chi2, l.score.chi2, floor0);
            if partial(&l, base) {
                l.interpretation = format!("beyond {}: {}", r.effect, l.interpretation);
                located.push(l);
            }
        }
    }
    located.sort_by(|a, b| aicc(a).total_cmp(&aicc(b)));
    // Can this design tell the two best partial findings apart?
    let rival = located.first().and_then(|a| {
        located[1..]
            .iter()
            .find(|b| !a.same_finding(b, data) && (aicc(b) - aicc(a)).abs() < s.clear_margin)
            .map(|b| {
                let g = best_discriminating_case(data, &a.model, &b.model);
                (a.describe(), b.describe(), g)
            })
    });
    Decision::Unexplained {
        closest,
        partial: located,
        rival,
    }
}

/// The catalogue's own decision when some catalogue variant reaches the floor.
fn catalogue<'a>(
    e: &Evidence<'a>,
    pool: &'a [Candidate],
    best: &'a Candidate,
    s: &DiagnoseSettings,
) -> Decision<'a> {
    let base = e.base;
    let best_aicc = best.score.aicc.unwrap_or(f64::INFINITY);
    let rivals: Vec<&Candidate> = pool
        .iter()
        .filter(|c| {
            c.effect != best.effect
                && c.score.at_noise_floor
                && c.score.cv_mare < base.mare
                && c.score.aicc.unwrap_or(f64::INFINITY) - best_aicc < s.clear_margin
        })
        .collect();
    let fraction = explained_fraction(base.chi2, best.score.chi2, floor0(base));
    // A variant that does not beat the baseline out of sample is never
    // reported, whatever its rivals.
    if best.score.cv_mare >= base.mare {
        return Decision::NotOutOfSample { best };
    }
    if rivals.is_empty() {
        return Decision::Catalogue { best, fraction };
    }
    let suggestion = best_discriminating_case(e.data, &best.model, &rivals[0].model);
    let mut names: Vec<String> = vec![best.effect.clone()];
    names.extend(rivals.iter().map(|r| r.effect.clone()));
    Decision::CatalogueRivals {
        names,
        suggestion,
        fraction,
    }
}
