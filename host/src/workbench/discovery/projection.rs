//! The added-variable screen: a law screened on top of fitted members is
//! scored with the members' parameters free, to first order.
//!
//! A law screened on the response table of a model holds the members
//! already in it at their fitted values. When a member took a share of the
//! effect the new law describes, the screen charges the law for what the
//! member would give back once both are refitted, and ranks first the law
//! that is least like the members, not the one the data want. Linearising
//! the members about their fit, the joint least-squares problem in the new
//! law's parameters `theta` and the members' shifts `delta` is
//!
//! `min ||r(theta) + J delta||^2 = min_theta ||P r(theta)||^2`,
//! `P = I - Q Q^T`,
//!
//! with `J` the members' Jacobian of the weighted residuals and `Q` an
//! orthonormal basis of its columns: the law is fitted to what the members
//! cannot mimic (the added-variable, or partial-regression, view; selecting
//! by it is orthogonal least squares forward selection). At the members'
//! optimum `J^T r(0) = 0`, so the law that does nothing scores exactly the
//! set's chi-square. The exact joint refit of the few best follows, as for
//! every screened law.
//!
//! References: S. Chen, S. A. Billings & W. Luo, Int. J. Control 50 (1989)
//! 1873 (orthogonal least squares selection); G. H. Golub & V. Pereyra,
//! SIAM J. Numer. Anal. 10 (1973) 413 (variable projection); R. D. Cook &
//! S. Weisberg, *Residuals and Influence in Regression* (1982), sec. 2.3.2
//! (added-variable plots).

use super::screen::{predictions, Table};
use crate::data::Dataset;
use crate::model::Model;

/// The directions the members' parameters move the weighted residuals in,
/// on every observation of a table.
pub struct Span {
    /// One column per free parameter, one entry per observation.
    cols: Vec<Vec<f64>>,
}

/// An orthonormal basis of a [`Span`] on a subset of the observations.
pub struct Basis {
    q: Vec<Vec<f64>>,
}

impl Span {
    /// The span of the free parameters of `model`'s effects from index
    /// `first` on, by forward differences of the exact model at its values;
    /// `None` when there are none or a perturbed model fails.
    pub fn of(model: &Model, first: usize, data: &Dataset, table: &Table) -> Option<Span> {
        let mut cols = Vec::new();
        for e in first..model.effects.len() {
            let inst = &model.effects[e];
            let specs = inst.effect.params();
            for p in inst.free_indices() {
                let (v, s) = (inst.values[p], &specs[p]);
                // A relative step far above rounding and far below the
                // parameter's scale; inward at an upper bound.
                let h = 1e-5 * (1.0 + v.abs());
                let h = if v + h > s.max { -h } else { h };
                let mut m = model.clone();
                m.effects[e].values[p] = v + h;
                let y = predictions(&m, data).ok()?;
                let col: Vec<f64> = y
                    .iter()
                    .zip(&table.base)
                    .zip(&table.obs)
                    .map(|((a, b), ob)| (a - b) / h / ob.sigma)
                    .collect();
                if col.iter().all(|x| x.is_finite()) {
                    cols.push(col);
                }
            }
        }
        (!cols.is_empty()).then_some(Span { cols })
    }

    /// An orthonormal basis on the observations `rows` (modified
    /// Gram-Schmidt; a column the others already span is dropped).
    // Written out rather than taken from nalgebra's QR: an unpivoted QR
    // keeps a column of Q for a member parameter the others already span
    // (two members whose strengths trade), normalised from rounding
    // noise, and removing that arbitrary direction would bias every law's
    // score; the rank must be decided column by column, as here.
    pub fn basis(&self, rows: &[usize]) -> Basis {
        let mut q: Vec<Vec<f64>> = Vec::new();
        for col in &self.cols {
            let mut v: Vec<f64> = rows.iter().map(|&o| col[o]).collect();
            let norm0 = dot(&v, &v).sqrt();
            for b in &q {
                let c = dot(&v, b);
                v.iter_mut().zip(b).for_each(|(x, y)| *x -= c * y);
            }
            let norm = dot(&v, &v).sqrt();
            if norm > 1e-8 * norm0 && norm > 0.0 {
                v.iter_mut().for_each(|x| *x /= norm);
                q.push(v);
            }
        }
        Basis { q }
    }
}

impl Basis {
    /// `r` less its part in the span: what the members cannot take up.
    pub fn remove(&self, r: &mut [f64]) {
        for b in &self.q {
            let c = dot(r, b);
            r.iter_mut().zip(b).for_each(|(x, y)| *x -= c * y);
        }
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::effects::correction::{Form, LocatedCorrection};
    use crate::effects::place::Place;
    use crate::effects::EffectInstance;
    use crate::workbench::discovery::screen::CaseFeature;
    use crate::workbench::fit::{fit_with, free_params_of};
    use crate::workbench::robust::Likelihood;
    use std::sync::Arc;

    fn constant_load() -> Arc<LocatedCorrection> {
        Arc::new(LocatedCorrection::new(Place::LoadForce, None, Form::Constant, 1.0, 1.0).unwrap())
    }

    fn with_load(model: &Model, v: f64) -> Model {
        model.clone().with_effect(EffectInstance {
            effect: constant_load().into(),
            values: vec![v],
        })
    }

    fn chi2(r: &[f64]) -> f64 {
        r.iter().map(|x| x * x).sum()
    }

    /// The force balance is linear in an axial load: a second constant load
    /// on top of a member that is one adds nothing the member cannot take
    /// up, whatever its value, once the member is free.
    #[test]
    fn a_law_the_members_can_mimic_exactly_scores_the_same_at_every_value() {
        let data = crate::data::paper();
        let model = with_load(&Model::base(), 0.3);
        let table = Table::build(&model, &data).unwrap();
        let span = Span::of(&model, Model::base().effects.len(), &data, &table).unwrap();
        let all: Vec<usize> = (0..table.obs.len()).collect();
        let basis = span.basis(&all);
        let c = constant_load();
        let xs = CaseFeature::new(vec![1.0; data.cases.len()]);
        let (mut held, mut free) = (Vec::new(), Vec::new());
        for v in [-2.0, -0.5, 0.0, 0.7, 3.0] {
            let mut r = Vec::new();
            table.residuals_into(&c, &[v], &xs, &all, &mut r);
            held.push(chi2(&r));
            basis.remove(&mut r);
            free.push(chi2(&r));
        }
        // Held, the load moves the chi-square by millions; free, by what
        // rounding leaves.
        let spread = |v: &[f64]| v.iter().fold(0.0_f64, |m, x| m.max((x - v[2]).abs()));
        assert!(spread(&held) > 1e6, "held: {held:?}");
        assert!(spread(&free) < 1e-6 * spread(&held), "free: {free:?}");
    }

    /// At the members' least-squares optimum the residual is orthogonal to
    /// their span: the law that does nothing scores the set's chi-square.
    #[test]
    fn at_the_members_optimum_nothing_added_scores_the_sets_chi_square() {
        let data = crate::data::paper();
        let start = with_load(&Model::base(), 0.0);
        let n0 = Model::base().effects.len();
        let free = free_params_of(&start, &[n0]);
        let fit = fit_with(&start, &data, None, &free, false, Likelihood::Gaussian).unwrap();
        let table = Table::build(&fit.model, &data).unwrap();
        let span = Span::of(&fit.model, n0, &data, &table).unwrap();
        let all: Vec<usize> = (0..table.obs.len()).collect();
        let mut r: Vec<f64> = (0..table.obs.len())
            .map(|o| (table.base[o] - table.obs[o].observed) / table.obs[o].sigma)
            .collect();
        let before = chi2(&r);
        span.basis(&all).remove(&mut r);
        let rel = (before - chi2(&r)) / before;
        assert!((0.0..1e-6).contains(&rel), "chi2 {before} -> {}", chi2(&r));
    }

    #[test]
    fn the_basis_is_orthonormal_drops_repeated_directions_and_removes_once() {
        let a = vec![1.0, 2.0, 0.5, -1.0, 3.0];
        let b = vec![0.0, 1.0, -1.0, 2.0, 0.5];
        let twice: Vec<f64> = a.iter().map(|x| 2.0 * x).collect();
        let span = Span {
            cols: vec![a, twice, b],
        };
        let rows = [0, 1, 2, 3, 4];
        let basis = span.basis(&rows);
        assert_eq!(basis.q.len(), 2);
        for (i, u) in basis.q.iter().enumerate() {
            for (j, v) in basis.q.iter().enumerate() {
                let want = if i == j { 1.0 } else { 0.0 };
                assert!((dot(u, v) - want).abs() < 1e-12);
            }
        }
        let mut r = vec![0.3, -1.2, 2.0, 0.1, 0.7];
        basis.remove(&mut r);
        let once = r.clone();
        basis.remove(&mut r);
        assert!(r.iter().zip(&once).all(|(x, y)| (x - y).abs() < 1e-12));
        assert!(basis.q.iter().all(|u| dot(u, &once).abs() < 1e-12));
        // On a subset of rows the basis spans the columns restricted to it.
        assert_eq!(span.basis(&[0, 2]).q.len(), 2);
        assert_eq!(span.basis(&[3]).q.len(), 1);
    }
}
