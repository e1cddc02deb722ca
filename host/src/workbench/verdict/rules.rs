//! The tests a located law must pass to be a finding of `diagnose`'s
//! verdict ([`super`]): supported (at the floor, better out of
//! sample, its drop above the search's charge in chi-square and in the
//! Student-t deviance), parsimonious among its neighbours, and its rivals.
//!
//! Reference: Burnham & Anderson (2002), sec. 2.6 (AICc differences);
//! Lange, Little & Taylor, JASA 84 (1989) 881 (the Student-t deviance).

use crate::data::Dataset;
use crate::workbench::diagnosis::Baseline;
use crate::workbench::discovery::{Discovery, Located};

/// Share of the excess a partial finding must remove to be shown.
pub const PARTIAL: f64 = 0.5;

pub fn aicc(l: &Located) -> f64 {
    l.score.aicc.unwrap_or(f64::INFINITY)
}

/// The finding to report from a discovery: among supported corrections
/// within the AICc margin of the best at the best's place, the one with the
/// fewest parameters (a near-constant law with a free exponent is not a
/// finding about its feature), ties by AICc.
pub fn parsimonious<'a>(
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
    2.0 * crate::workbench::experiments::separation::median_rel_se(data)
        * (2.0 / std::f64::consts::PI).sqrt()
}

/// Whether a located correction is a finding: at the noise floor, or (an
/// approximate law) removing 95 % of the excess with a cross-validated
/// MARE at the noise level; its CV MARE below the baseline's; and its
/// chi-square drop above `2k + 2 ln M` (see [`super`]).
pub fn supported(l: &Located, base: &Baseline, searched: usize, data: &Dataset) -> bool {
    let k = l.params.len() as f64;
    let approximate =
        l.explained_fraction.is_some_and(|f| f >= 0.95) && l.score.cv_mare <= noise_mare(data);
    let cost = 2.0 * k + 2.0 * (searched.max(1) as f64).ln();
    (l.score.at_noise_floor || approximate)
        && l.score.cv_mare < base.mare
        && base.chi2 - l.score.chi2 >= cost
        && base.t_deviance - l.t_deviance >= cost
}

/// A partial finding: removes at least [`PARTIAL`] and lowers MARE.
pub fn partial(l: &Located, base: &Baseline) -> bool {
    l.explained_fraction.is_some_and(|f| f >= PARTIAL) && l.score.mare < base.mare
}

/// Rivals of `best` among `pool`: supported, within the margin, and a
/// different finding (another place; or, when `best` scales with a
/// feature, a non-equivalent feature at the same place). A feature law at
/// the place of a constant `best` is not a rival: parsimony already chose
/// the constant. One rival per finding.
pub fn rivals<'a>(
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
