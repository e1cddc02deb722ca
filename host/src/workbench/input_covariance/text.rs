//! The words for the chi-square with the inputs' covariance and for the
//! shared inputs' pulls ([`crate::workbench::input_covariance`]): the one wording that
//! `compare` (table and JSON's `chi2_correlated`) and the page print.
//!
//! References: see [`crate::workbench::input_covariance`].

use super::{CorrelatedChi2, Pull};
use crate::format::fmt_sig;

/// A p-value to two significant figures, or its bound below 1e-12.
fn p_text(p: f64) -> String {
    if p < 1e-12 {
        "< 1e-12".into()
    } else {
        format!("= {}", fmt_sig(p, 2))
    }
}

impl CorrelatedChi2 {
    /// The statistic in one sentence, e.g. "chi-square 45.3 on 12 degrees
    /// of freedom with the inputs' covariance across cases (reduced 3.78,
    /// p = 3.1e-6)".
    pub fn describe(&self) -> String {
        let tail = match (self.chi2_reduced, self.p_value) {
            (Some(r), Some(p)) => format!(" (reduced {}, p {})", fmt_sig(r, 3), p_text(p)),
            _ => String::new(),
        };
        format!(
            "chi-square {} on {} degrees of freedom with the inputs' covariance across cases{tail}",
            fmt_sig(self.chi2, 3),
            self.dof.unwrap_or(0),
        )
    }

    /// The statistics that leave correlations out, labelled as such.
    pub fn describe_independent(&self) -> String {
        let cases = self.chi2_cases_independent.map_or(String::new(), |c| {
            format!(
                ", {} with the cases taken as independent (each case's U and Omega_b \
                 correlated by its own inputs)",
                fmt_sig(c, 3)
            )
        });
        format!(
            "{} with every quantity taken as independent{cases}; neither follows chi-square \
             when inputs are shared",
            fmt_sig(self.chi2_independent, 3)
        )
    }
}

impl Pull {
    /// "net_weight_g +0.017 (+0.17 ± 0.52 declared standard uncertainties,
    /// shared by 6 cases)".
    pub fn describe(&self) -> String {
        let signed = |x: f64, d: usize| {
            let s = fmt_sig(x, d);
            if x >= 0.0 {
                format!("+{s}")
            } else {
                s
            }
        };
        format!(
            "{} {} ({} ± {} declared standard uncertainties, shared by {} case{})",
            self.input,
            signed(self.shift, 2),
            signed(self.pull_sigmas, 2),
            fmt_sig(self.pull_sd_sigmas, 2),
            self.cases,
            if self.cases == 1 { "" } else { "s" }
        )
    }
}
