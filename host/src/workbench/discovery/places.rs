//! The best law at each place: the exact refits of [`super::discover`]
//! take the top of one ranking, and on the drawn two-effect truth they all
//! sit at one place, so backfitting never tried another. This screens every
//! law on the table (the same search, [`super::search`]) and keeps the best
//! at each place the model is sensitive to; the caller refits it exactly,
//! jointly with the members of a set ([`crate::workbench::search`]).
//!
//! References: Burnham & Anderson, *Model Selection and Multimodel
//! Inference*, 2nd ed. (2002) (AICc ranking).

use super::screen::Table;
use super::search::{Screen, Screened};
use super::{aicc, refit, Located, Reference};
use crate::data::Dataset;
use crate::effects::place::Place;
use crate::model::Model;
use crate::workbench::fit::FitError;

/// The best screened law at one place, with what its exact refit needs.
pub struct AtPlace {
    pub place: Place,
    pub screened: Screened,
}

/// The best screened law at each sensitive place on the response `table`
/// of a model (`k`: free parameters already fitted, counted in the
/// ranking's AICc). The table and its screen are the caller's: the search
/// on the same model ([`super::discover_on`]) reads them too, and building
/// them is most of the cost on small data.
pub fn best_at_each_place(table: &Table, screen: &Screen, k: usize) -> Vec<AtPlace> {
    let mut out: Vec<AtPlace> = Vec::new();
    for place in Place::ALL {
        let Some(&x) = best_at(screen, place, k, 1).first() else {
            continue;
        };
        let mut x = x.clone();
        screen.on_all(table, &mut x);
        out.push(AtPlace { place, screened: x });
    }
    out
}

/// The `n` best screened laws at `place`, by screened AICc on top of `k`
/// parameters already fitted (ties keep the screen's order).
pub fn best_at(screen: &Screen, place: Place, k: usize, n: usize) -> Vec<&Screened> {
    let n_sub = screen.sub.len();
    let key = |x: &Screened| aicc(x.chi2, n_sub, k + x.params.len()).unwrap_or(x.chi2);
    let mut v: Vec<&Screened> = screen
        .screened
        .iter()
        .filter(|x| x.correction.place == place)
        .collect();
    v.sort_by(|a, b| key(a).total_cmp(&key(b)));
    v.truncate(n);
    v
}

impl AtPlace {
    /// The exact refit of this law alone on top of `model` (the finding a
    /// path records once the law is kept).
    pub fn locate(
        &self,
        model: &Model,
        data: &Dataset,
        reference: &Reference,
    ) -> Result<Located, FitError> {
        let floor0 = (reference.floor)(0);
        // No cross-validation here: a law kept in a set is restated at the
        // set's joint values with its exact cross-validated MARE
        // (`search::set::restate`); ten table refits per place per call
        // were most of the search's time on 1000 cases.
        refit(
            model,
            data,
            self.screened.clone(),
            f64::NAN,
            reference,
            floor0,
        )
    }
}
