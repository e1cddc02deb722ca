//! A feature: a per-case number a law can scale with. Either one of the
//! library's quantities ([`super::quantities`]: geometry, kinematics, the
//! setup's fields, the model's own quantities), known when the tool is
//! built, or a numeric column the lab recorded ([`super::recorded`]: the
//! oil's temperature, the days since the tube was filled, the robot's id),
//! known only when the data are read.
//!
//! A lab records a column because it suspects it matters, so a recorded
//! column is offered to the search like a library quantity. Its name is
//! the lab's; a formula reads it as `recorded.NAME`
//! ([`crate::effects::expr`]), so only a name that is an identifier
//! (`[a-z_][a-z0-9_]*`) can be written into an effect file and searched.

use super::quantities::Quantity;
use super::Case;
use std::borrow::Cow;
use std::sync::Arc;

/// What a formula writes before a recorded column's name.
pub const RECORDED_PREFIX: &str = "recorded.";

/// A per-case number a law can scale with.
#[derive(Clone)]
pub enum Feature {
    Quantity(&'static Quantity),
    /// A numeric column the lab recorded, by its name.
    Recorded(Arc<str>),
}

impl Feature {
    /// The recorded column `name`, when the name can be read in a formula.
    pub fn recorded(name: &str) -> Option<Feature> {
        is_identifier(name).then(|| Feature::Recorded(name.into()))
    }

    /// The id a formula reads: the quantity's id, or `recorded.NAME`.
    pub fn id(&self) -> Cow<'static, str> {
        match self {
            Feature::Quantity(q) => Cow::Borrowed(q.id),
            Feature::Recorded(n) => Cow::Owned(format!("{RECORDED_PREFIX}{n}")),
        }
    }

    /// In words: the quantity's formula in the paper's symbols, or the
    /// column's name marked as recorded.
    pub fn name(&self) -> Cow<'static, str> {
        match self {
            Feature::Quantity(q) => Cow::Borrowed(q.name),
            Feature::Recorded(n) => Cow::Owned(format!("{n} (recorded)")),
        }
    }

    /// Its value on a case (NaN for a recorded column the case lacks).
    pub fn of(&self, case: &Case) -> f64 {
        match self {
            Feature::Quantity(q) => q.of(case),
            Feature::Recorded(n) => case.recorded.value(n).unwrap_or(f64::NAN),
        }
    }

    /// The library quantity, `None` for a recorded column.
    pub fn quantity(&self) -> Option<&'static Quantity> {
        match self {
            Feature::Quantity(q) => Some(q),
            Feature::Recorded(_) => None,
        }
    }

    pub fn is_recorded(&self) -> bool {
        matches!(self, Feature::Recorded(_))
    }

    /// Whether two features are the same column (not merely equivalent
    /// on a design: [`crate::workbench::discovery::equivalent`]).
    pub fn same(&self, other: &Feature) -> bool {
        match (self, other) {
            (Feature::Quantity(a), Feature::Quantity(b)) => a.id == b.id,
            (Feature::Recorded(a), Feature::Recorded(b)) => a == b,
            _ => false,
        }
    }
}

impl std::fmt::Debug for Feature {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.id())
    }
}

/// `[a-z_][a-z0-9_]*`: what the formula language reads as a name.
fn is_identifier(name: &str) -> bool {
    let mut chars = name.chars();
    chars
        .next()
        .is_some_and(|c| c.is_ascii_lowercase() || c == '_')
        && chars.all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_')
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_recorded_column_reads_the_case_and_is_nan_where_missing() {
        let mut case = crate::data::paper().cases[0].clone();
        case.recorded.values.push(("temperature_c".into(), 21.5));
        let t = Feature::recorded("temperature_c").unwrap();
        assert_eq!(t.of(&case), 21.5);
        assert_eq!(t.id(), "recorded.temperature_c");
        assert_eq!(t.name(), "temperature_c (recorded)");
        assert!(Feature::recorded("day").unwrap().of(&case).is_nan());
    }

    #[test]
    fn only_identifier_names_are_features() {
        assert!(Feature::recorded("oil_t2").is_some());
        for bad in ["", "Temp", "2nd", "oil temp", "t-c", "a.b"] {
            assert!(Feature::recorded(bad).is_none(), "{bad}");
        }
    }

    #[test]
    fn sameness_is_by_column_not_by_kind() {
        let q = super::super::quantities::by_id("wire_over_gap").unwrap();
        let (a, b) = (Feature::Quantity(q), Feature::Quantity(q));
        assert!(a.same(&b));
        let r = Feature::recorded("wire_over_gap_x").unwrap();
        assert!(!a.same(&r) && r.same(&r.clone()));
    }
}
