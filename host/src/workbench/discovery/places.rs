//! The best law at each place: the exact refits of [`super::discover`]
//! take the top of one ranking, and on the drawn two-effect truth they all
//! sit at one place, so backfitting never tried another. This screens every
//! law on the table (the same search, [`super::search`]) and keeps the best
//! at each place the model is sensitive to; the caller refits it exactly,
//! jointly with the steps it keeps ([`crate::workbench::subsets`]).
//!
//! References: Burnham & Anderson, *Model Selection and Multimodel
//! Inference*, 2nd ed. (2002) (AICc ranking).

use super::screen::Table;
use super::search::{cv_mare, Screen, Screened};
use super::{aicc, refit, DiscoverySettings, Located, Reference};
use crate::data::Dataset;
use crate::effects::place::Place;
use crate::model::Model;
use crate::workbench::fit::FitError;

/// The best screened law at one place, with what its exact refit needs.
pub struct AtPlace {
    pub place: Place,
    pub screened: Screened,
    cv_mare: f64,
}

/// The best screened law at each sensitive place on the response `table`
/// of a model (`k`: free parameters already fitted, counted in the
/// ranking's AICc). The table and its screen are the caller's: the search
/// on the same model ([`super::discover_on`]) reads them too, and building
/// them is most of the cost on small data.
pub fn best_at_each_place(
    table: &Table,
    screen: &Screen,
    data: &Dataset,
    k: usize,
    s: &DiscoverySettings,
) -> Vec<AtPlace> {
    let n_cases = data.cases.len();
    let n_sub = screen.sub.len();
    let key = |x: &Screened| aicc(x.chi2, n_sub, k + x.params.len()).unwrap_or(x.chi2);
    let folds = if n_cases <= 10 { n_cases } else { s.folds };
    let mut out: Vec<AtPlace> = Vec::new();
    for place in Place::ALL {
        let best = screen
            .screened
            .iter()
            .filter(|x| x.correction.place == place)
            .min_by(|a, b| key(a).total_cmp(&key(b)));
        let Some(x) = best else { continue };
        let mut x = x.clone();
        screen.on_all(table, &mut x);
        let cv = cv_mare(table, &x, n_cases, folds);
        out.push(AtPlace {
            place,
            screened: x,
            cv_mare: cv,
        });
    }
    out
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
        refit(
            model,
            data,
            self.screened.clone(),
            self.cv_mare,
            reference,
            floor0,
        )
    }
}
