//! Two laws at the speed-only places chosen together, on the force balance
//! itself.
//!
//! In the paper's drive eq. 11 splits into
//! `U = (F - B_t[x,wx] omega) / (D_x + B_t[x,x] + B_x[x,x])` and
//! `Omega_b = (T - B_t[wx,wx] omega) / E_x`: the body's axial drag, the
//! tail's axial drag and its thrust coupling (`body.D_x`, `tail.drag`,
//! `tail.thrust`) set the speed alone
//! ([`crate::workbench::discovery::interpret::equivalents`]). Two laws
//! there act on one number per case, and a law screened on top of the
//! other takes a share of its effect: the screened best at the second
//! place is biased by the first, and no single replacement gives the share
//! back. Here every pair of the [`PER_PLACE`] best screened laws at two of
//! those places (screened on the model of the members kept, held at their
//! values) is fitted jointly on the speeds, exactly, on the cases the
//! screen fits on (every case up to `screen_cases`): with those members
//! held, each case's balance is read once
//! ([`Model::force_balance`]), and a pair's speeds are that formula with
//! the two multipliers in it, no model solve. The [`KEPT`] best pairs by
//! the speeds' chi-square are refitted with the set, jointly and exactly,
//! as every set of the search is ([`super::exchange`]).
//!
//! When the balance does not split (a motor rate relative to the body, a
//! body or extra resistance coupling translation with rotation, more
//! degrees of freedom), nothing is offered.
//!
//! References: A. J. Miller, *Subset Selection in Regression*, 2nd ed.
//! (2002), ch. 3 (replacing more than one variable at a time).

use super::fitted::Ctx;
use super::screened::{pending_member, OnModel};
use super::set::Member;
use crate::data::Dataset;
use crate::effects::correction::MIN_MULTIPLIER;
use crate::effects::place::Place;
use crate::effects::Effect;
use crate::model::Model;
use crate::physics::solve::{Dofs, TailDrive};
use crate::workbench::discovery::least_squares::least_squares;
use crate::workbench::discovery::places::{best_at, AtPlace};
use crate::workbench::discovery::search::Screened;
use rayon::prelude::*;

/// The places that set the speed alone in the paper's drive.
const SPEED_PLACES: [Place; 3] = [Place::BodyTranslation, Place::TailDrag, Place::TailThrust];

/// Screened laws per speed-only place whose pairs are fitted (20).
pub const PER_PLACE: usize = 20;

/// Pairs refitted exactly with the set, per kept member (3).
pub const KEPT: usize = 3;

/// One case's speed balance with the set's other members held.
struct SpeedBalance {
    /// `F` (N), `B_t[x,wx] omega` (N), `D_x`, `B_t[x,x]`, `B_x[x,x]` (N s/m).
    load: f64,
    thrust: f64,
    body: f64,
    tail: f64,
    extra: f64,
    observed_mm_s: f64,
    sigma_mm_s: f64,
}

impl SpeedBalance {
    /// The speed (mm/s) with multipliers on the body's drag, the tail's
    /// drag and the thrust.
    fn speed_mm_s(&self, [m_body, m_drag, m_thrust]: [f64; 3]) -> f64 {
        1e3 * (self.load - m_thrust * self.thrust)
            / (m_body * self.body + m_drag * self.tail + self.extra)
    }
}

/// The speed balance under `model` of every case `keep` admits, or `None`
/// when it does not split (module docs).
fn balances(
    model: &Model,
    data: &Dataset,
    keep: impl Fn(usize) -> bool,
) -> Option<Vec<(usize, SpeedBalance)>> {
    let mut out = Vec::new();
    for (i, case) in data.cases.iter().enumerate().filter(|(i, _)| keep(*i)) {
        let fb = model.force_balance(case).ok()?;
        let coupled = [fb.body, fb.extra]
            .iter()
            .any(|m| m[(0, 3)] != 0.0 || m[(3, 0)] != 0.0);
        if fb.drive != TailDrive::Absolute || fb.dofs != Dofs::AXIAL || coupled {
            return None;
        }
        let Some(u) = &case.u_mm_s else { continue };
        out.push((
            i,
            SpeedBalance {
                load: fb.load[0],
                thrust: fb.tail[(0, 3)] * fb.tail_rate_rad_s,
                body: fb.body[(0, 0)],
                tail: fb.tail[(0, 0)],
                extra: fb.extra[(0, 0)],
                observed_mm_s: u.mean,
                sigma_mm_s: u.standard_error(),
            },
        ));
    }
    Some(out)
}

/// The pairs of laws at two speed-only places that replace two members of
/// a set whose `kept` members stay: the [`KEPT`] best by the speeds'
/// joint chi-square, as pending members with their jointly fitted values.
pub(super) fn speed_pairs(
    ctx: &Ctx,
    kept: &[Member],
    on: &OnModel,
    law_charge: f64,
) -> Vec<[Member; 2]> {
    let taken: Vec<&str> = kept.iter().filter_map(|m| m.place).collect();
    let free: Vec<Place> = SPEED_PLACES
        .into_iter()
        .filter(|p| !taken.contains(&p.name()))
        .collect();
    if free.len() < 2 {
        return Vec::new();
    }
    // On the cases the screen fits on (a stride above `screen_cases`): the
    // pairs are ranked as the laws were, and refitted on every case.
    let screen = &on.held;
    let Some(cases) = balances(&on.model, ctx.data, |i| screen.screens_case(i)) else {
        return Vec::new();
    };
    let k0 = kept.iter().map(Member::n_params).sum::<usize>();
    let best: Vec<Vec<&Screened>> = free
        .iter()
        .map(|&p| best_at(screen, p, k0, PER_PLACE))
        .collect();
    let mut pairs: Vec<(&Screened, &Screened)> = Vec::new();
    for i in 0..free.len() {
        for j in i + 1..free.len() {
            pairs.extend(
                best[i]
                    .iter()
                    .flat_map(|a| best[j].iter().map(move |b| (*a, *b))),
            );
        }
    }
    let mut fitted: Vec<(f64, Screened, Screened)> = pairs
        .par_iter()
        .map(|(a, b)| fit_pair(&cases, a, b))
        .filter(|x| x.0.is_finite())
        .collect();
    fitted.sort_by(|x, y| x.0.total_cmp(&y.0));
    fitted
        .into_iter()
        .take(KEPT)
        .map(|(_, a, b)| [member(a, law_charge), member(b, law_charge)])
        .collect()
}

fn member(s: Screened, law_charge: f64) -> Member {
    let place = s.correction.place;
    pending_member(AtPlace { place, screened: s }, law_charge)
}

/// Which of the three multipliers a law at `place` sets.
fn slot(place: Place) -> usize {
    SPEED_PLACES
        .iter()
        .position(|&p| p == place)
        .expect("a speed-only place")
}

/// The speeds' normalised residuals of the pair at `p` (the first law's
/// parameters, then the second's) into `out`; returns their sum of squares
/// (infinite when it is not finite).
fn residuals(
    cases: &[(usize, SpeedBalance)],
    laws: [&Screened; 2],
    p: &[f64],
    out: &mut Vec<f64>,
) -> f64 {
    let (pa, pb) = p.split_at(laws[0].params.len());
    out.clear();
    for (i, b) in cases {
        let mut m = [1.0; 3];
        for (law, q) in laws.iter().zip([pa, pb]) {
            let x = law.xs.x[*i];
            m[slot(law.correction.place)] = law.correction.law(q, x).max(MIN_MULTIPLIER);
        }
        out.push((b.speed_mm_s(m) - b.observed_mm_s) / b.sigma_mm_s);
    }
    let sum: f64 = out.iter().map(|r| r * r).sum();
    if sum.is_finite() {
        sum
    } else {
        f64::INFINITY
    }
}

/// The pair fitted jointly on the speeds by the screens' bounded
/// Levenberg-Marquardt ([`least_squares`]) from the laws' screened values;
/// returns the chi-square and the laws at their joint values.
fn fit_pair(
    cases: &[(usize, SpeedBalance)],
    a: &Screened,
    b: &Screened,
) -> (f64, Screened, Screened) {
    let bounds: Vec<(f64, f64)> = [a, b]
        .iter()
        .flat_map(|s| s.correction.params().iter().map(|q| (q.min, q.max)))
        .collect();
    let start: Vec<f64> = a.params.iter().chain(&b.params).copied().collect();
    let mut r = |p: &[f64], out: &mut Vec<f64>| residuals(cases, [a, b], p, out);
    let (p, chi2) = least_squares(&mut r, &start, &bounds);
    let (pa, pb) = p.split_at(a.params.len());
    let with = |s: &Screened, q: &[f64]| Screened {
        params: q.to_vec(),
        chi2,
        ..s.clone()
    };
    (chi2, with(a, pa), with(b, pb))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::data::quantities::by_id;
    use crate::effects::correction::{Form, LocatedCorrection};
    use crate::effects::EffectInstance;
    use crate::workbench::discovery::search::xs_of;
    use std::sync::Arc;

    fn law(place: Place, feature: &str, form: Form) -> Arc<LocatedCorrection> {
        let data = crate::data::paper();
        let q = by_id(feature).unwrap();
        let mut v: Vec<f64> = data.cases.iter().map(|c| q.of(c)).collect();
        v.sort_by(f64::total_cmp);
        Arc::new(
            LocatedCorrection::new(
                place,
                Some(crate::data::Feature::Quantity(q)),
                form,
                v[v.len() / 2],
                1.0,
            )
            .unwrap(),
        )
    }

    fn with(model: &Model, c: &Arc<LocatedCorrection>, p: &[f64]) -> Model {
        model.clone().with_effect(EffectInstance {
            effect: c.clone().into(),
            values: p.to_vec(),
        })
    }

    /// The speed read from a case's balance with the multipliers in it is
    /// the model's own prediction with the laws added, on every case.
    #[test]
    fn the_speed_formula_is_the_models_prediction() {
        let data = crate::data::paper();
        let a = law(Place::BodyTranslation, "body_ratio", Form::Power);
        let b = law(Place::TailThrust, "helix_over_gap", Form::PowerLaw);
        let (pa, pb) = ([0.4, 2.0], [0.8, -0.5]);
        let model = with(&with(&Model::base(), &a, &pa), &b, &pb);
        let cases = balances(&Model::base(), &data, |_| true).unwrap();
        for (i, bal) in &cases {
            let case = &data.cases[*i];
            let m = [a.value(&pa, case), 1.0, b.value(&pb, case)];
            let exact = model.predict(case).unwrap().u_mm_s;
            assert!(
                (bal.speed_mm_s(m) / exact - 1.0).abs() < 1e-12,
                "{}",
                case.id
            );
        }
    }

    /// A motor rate relative to the body couples speed and rotation: the
    /// balance does not split, and nothing is offered.
    #[test]
    fn a_coupled_balance_offers_nothing() {
        let data = crate::data::paper();
        let relative =
            Model::base().with_effect(crate::effects::parse_effect_spec("motor-frame").unwrap());
        assert!(balances(&relative, &data, |_| true).is_none());
    }

    /// Speeds made by a body-drag law and a tail-drag law together are
    /// fitted back to chi-square zero from the laws' values 30 % off.
    #[test]
    fn a_pair_that_made_the_speeds_is_fitted_back() {
        let mut data = crate::data::paper();
        let a = law(Place::BodyTranslation, "body_ratio", Form::Power);
        let b = law(Place::TailDrag, "helix_over_gap", Form::Power);
        let (pa, pb) = ([0.3, 1.5], [0.5, 1.0]);
        let truth = with(&with(&Model::base(), &a, &pa), &b, &pb);
        for c in &mut data.cases {
            let u = truth.predict(c).unwrap().u_mm_s;
            c.u_mm_s.as_mut().unwrap().mean = u;
        }
        let cases = balances(&Model::base(), &data, |_| true).unwrap();
        let screened = |c: &Arc<LocatedCorrection>, p: &[f64]| Screened {
            correction: c.clone(),
            params: p.iter().map(|x| 1.3 * x).collect(),
            chi2: f64::NAN,
            xs: xs_of(c, &data),
        };
        let (chi2, fa, fb) = fit_pair(&cases, &screened(&a, &pa), &screened(&b, &pb));
        let start = residuals(
            &cases,
            [&screened(&a, &pa), &screened(&b, &pb)],
            &[0.39, 1.95, 0.65, 1.3],
            &mut Vec::new(),
        );
        assert!(start > 1e3, "{start}");
        assert!(
            chi2 < 1e-6 * start,
            "{chi2} from {start}: {:?} {:?}",
            fa.params,
            fb.params
        );
    }
}
