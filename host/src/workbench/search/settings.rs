//! The knobs of the search over sets ([`super`]): how many sets it keeps
//! and extends at each size, how far it looks on large data, and the
//! resamples behind each term's stability. `Default` gives the documented
//! values, the ones every verdict in the docs was measured with.
//!
//! They bound cost, not the criterion: every set that is fitted is ranked
//! by the same key (AICc plus the charge for the laws it was chosen from),
//! so a wider search can only find a lower key, never change what "lower"
//! means.

/// How wide the beam and the exchange run on one dataset.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Breadth {
    /// Sets of each size extended.
    pub beam: usize,
    /// Screened laws refitted jointly on top of each extended set.
    pub extend: usize,
    /// Places whose best single law is paired with each other's from
    /// scratch.
    pub paired: usize,
    /// Sets of each size exchanged member by member after the beam.
    pub exchange_width: usize,
    /// Laws tried in place of each member in an exchange.
    pub exchange_laws: usize,
}

/// Settings of the search; `Default` gives the documented values.
#[derive(Debug, Clone, PartialEq)]
pub struct SearchSettings {
    /// Most laws and effects in one set (3).
    pub max_laws: usize,
    /// Catalogue effects tried on top of each extended set (2).
    pub catalogue_extend: usize,
    /// How far above the noise floor the best acceptable set may stay for
    /// the joint ranking to choose (50 times its chi-square); beyond, the
    /// sets are nested (module docs of [`super`]).
    pub far_above: f64,
    /// Most rounds of exchange (2).
    pub exchange_rounds: usize,
    /// The breadth up to the discovery's
    /// [`large_above_cases`](crate::workbench::discovery::DiscoverySettings::large_above_cases)
    /// (beam 4, extend 8: nearly every other place, paired 8, exchange
    /// width 2 with 4 laws).
    pub breadth: Breadth,
    /// The breadth on larger data, where each fit costs proportionally
    /// more (beam 3, extend 3, paired 5, exchange width 1 with 3 laws).
    pub large: Breadth,
    /// When every single stays [`Self::far_above`] times above its floor,
    /// one set of each size is extended by 3 laws and no pairs are placed
    /// from scratch: the sets there rank misfits, and the choice nests
    /// them. The exchange keeps the breadth of the data's size.
    pub far: Breadth,
    /// Bootstrap resamples behind each located term's stability (200).
    pub resamples: usize,
}

impl Default for SearchSettings {
    fn default() -> Self {
        let breadth = Breadth {
            beam: 4,
            extend: 8,
            paired: 8,
            exchange_width: 2,
            exchange_laws: 4,
        };
        let large = Breadth {
            beam: 3,
            extend: 3,
            paired: 5,
            exchange_width: 1,
            exchange_laws: 3,
        };
        SearchSettings {
            max_laws: 3,
            catalogue_extend: 2,
            far_above: 50.0,
            exchange_rounds: 2,
            breadth,
            large,
            far: Breadth {
                beam: 1,
                extend: 3,
                paired: 0,
                ..breadth
            },
            resamples: 200,
        }
    }
}

impl SearchSettings {
    /// The breadth on `large` data, `far` when every single stays
    /// [`Self::far_above`] times above its floor: the beam's from the
    /// two, the exchange's from the data's size alone.
    pub fn breadth_for(&self, large: bool, far: bool) -> Breadth {
        let sized = if large { self.large } else { self.breadth };
        match far {
            true => Breadth {
                exchange_width: sized.exchange_width,
                exchange_laws: sized.exchange_laws,
                ..self.far
            },
            false => sized,
        }
    }

    /// Whether `chi2` with `floor` is farther above it than
    /// [`Self::far_above`] times (never without a floor).
    pub fn is_far(&self, chi2: f64, floor: Option<f64>) -> bool {
        floor.is_some_and(|fl| chi2 > self.far_above * fl)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn large_data_narrows_the_search_and_far_data_narrows_the_beam_only() {
        let s = SearchSettings::default();
        assert_eq!(s.breadth_for(false, false), s.breadth);
        assert_eq!(s.breadth_for(true, false), s.large);
        let far_small = s.breadth_for(false, true);
        assert_eq!(
            (far_small.beam, far_small.extend, far_small.paired),
            (1, 3, 0)
        );
        assert_eq!(far_small.exchange_width, s.breadth.exchange_width);
        let far_large = s.breadth_for(true, true);
        assert_eq!(far_large.exchange_laws, s.large.exchange_laws);
    }

    #[test]
    fn far_needs_a_floor_and_a_strict_excess() {
        let s = SearchSettings::default();
        assert!(!s.is_far(1e9, None));
        assert!(!s.is_far(500.0, Some(10.0)));
        assert!(s.is_far(500.1, Some(10.0)));
    }
}
