//! Formulas of user effects: a small arithmetic language compiled once into
//! a tree whose variables are bound by index, then evaluated per case.
//!
//! The grammar and its parser: `super::expr_parse`.
//!
//! Constants `pi`, `e`; functions of one argument `exp ln log10 sqrt abs sin
//! cos tan atan tanh`, of two `min max pow`; quantities are the ids of
//! [`crate::data::quantities`] (features and fields); parameters are the
//! effect's own.
//!
//! ## Why not an expression crate
//! The candidates were weighed against what this use needs: a formula is
//! evaluated per case per fit iteration, so it must be compiled once with
//! variables bound by index; load errors must give the column inside the
//! formula and the close matches of an unknown name; the agreed format has
//! two-argument functions `min(a, b)`, `max`, `pow`. `exmex` (maintained,
//! fast, index-bound) has no comma-separated function arguments and reports
//! no column; `evalexpr` (maintained) looks variables up by string in a
//! context at every evaluation and has integer arithmetic (`1/2 = 0`), a
//! trap for physics formulas; `fasteval` and `meval` are unmaintained. The
//! whole language is ~250 lines here, in `super::expr_parse` and
//! `super::expr_lex`, tested below, with exact positions.

pub use super::expr_lex::suggest;
use crate::data::quantities::Quantity;
use crate::data::Case;

/// A compiled formula.
#[derive(Clone)]
pub struct Expr {
    root: Node,
}

#[derive(Clone)]
pub(super) enum Node {
    Num(f64),
    Param(usize),
    Quantity(&'static Quantity),
    /// A column the lab recorded (`recorded.NAME`): NaN on a case
    /// without it, which an effect's check refuses.
    Recorded(std::sync::Arc<str>),
    Neg(Box<Node>),
    Bin(BinOp, Box<Node>, Box<Node>),
    /// `x^n` with a constant integer exponent: `powi` is exact and ~10x faster than `powf`.
    PowI(Box<Node>, i32),
    Call1(Fn1, Box<Node>),
    Call2(Fn2, Box<Node>, Box<Node>),
}

#[derive(Clone, Copy)]
pub(super) enum BinOp {
    Add,
    Sub,
    Mul,
    Div,
    Pow,
}

/// A formula that does not compile: `column` counts characters from 1.
#[derive(Debug, Clone, PartialEq)]
pub struct ExprError {
    pub column: usize,
    pub message: String,
}

type Fn1 = fn(f64) -> f64;
type Fn2 = fn(f64, f64) -> f64;

/// Functions of one argument.
pub const FUNCTIONS_1: &[(&str, Fn1)] = &[
    ("exp", f64::exp),
    ("ln", f64::ln),
    ("log10", f64::log10),
    ("sqrt", f64::sqrt),
    ("abs", f64::abs),
    ("sin", f64::sin),
    ("cos", f64::cos),
    ("tan", f64::tan),
    ("atan", f64::atan),
    ("tanh", f64::tanh),
];

/// Functions of two arguments.
pub const FUNCTIONS_2: &[(&str, Fn2)] = &[("min", f64::min), ("max", f64::max), ("pow", f64::powf)];

/// Named constants.
pub const CONSTANTS: &[(&str, f64)] = &[("pi", std::f64::consts::PI), ("e", std::f64::consts::E)];

/// Whether `name` is reserved by the language (a function or a constant).
pub fn is_reserved(name: &str) -> bool {
    FUNCTIONS_1.iter().any(|f| f.0 == name)
        || FUNCTIONS_2.iter().any(|f| f.0 == name)
        || CONSTANTS.iter().any(|c| c.0 == name)
}

impl Expr {
    /// Compile `text`; identifiers resolve to `params` (by position), then
    /// constants, then case quantities.
    /// Formulas longer than [`crate::data::limits::MAX_FORMULA_CHARS`] or nested deeper than
    /// [`crate::data::limits::MAX_FORMULA_DEPTH`] are errors (the parser and the evaluator recurse
    /// per level; without the limits a long formula overflowed the stack).
    pub fn parse(text: &str, params: &[&str]) -> Result<Expr, ExprError> {
        let root = super::expr_parse::parse(text, params)?;
        Ok(Expr { root })
    }

    /// Evaluate with parameter values `p` on `case`.
    pub fn eval(&self, p: &[f64], case: &Case) -> f64 {
        self.root.eval(p, case)
    }

    /// Indices of the parameters the formula uses.
    pub fn params_used(&self) -> Vec<usize> {
        let mut out = Vec::new();
        self.root.visit(&mut |n| {
            if let Node::Param(i) = n {
                out.push(*i);
            }
        });
        out.sort_unstable();
        out.dedup();
        out
    }

    /// Ids of the case quantities the formula uses.
    pub fn quantities_used(&self) -> Vec<&'static str> {
        let mut out = Vec::new();
        self.root.visit(&mut |n| {
            if let Node::Quantity(q) = n {
                out.push(q.id);
            }
        });
        out.sort_unstable();
        out.dedup();
        out
    }
}

impl Node {
    fn eval(&self, p: &[f64], case: &Case) -> f64 {
        match self {
            Node::Num(x) => *x,
            Node::Param(i) => p[*i],
            Node::Quantity(q) => q.of(case),
            Node::Recorded(n) => case.recorded.value(n).unwrap_or(f64::NAN),
            Node::Neg(a) => -a.eval(p, case),
            Node::Bin(op, a, b) => {
                let (a, b) = (a.eval(p, case), b.eval(p, case));
                match op {
                    BinOp::Add => a + b,
                    BinOp::Sub => a - b,
                    BinOp::Mul => a * b,
                    BinOp::Div => a / b,
                    BinOp::Pow => a.powf(b),
                }
            }
            Node::PowI(a, n) => a.eval(p, case).powi(*n),
            Node::Call1(f, a) => f(a.eval(p, case)),
            Node::Call2(f, a, b) => f(a.eval(p, case), b.eval(p, case)),
        }
    }

    fn visit(&self, f: &mut dyn FnMut(&Node)) {
        f(self);
        match self {
            Node::Neg(a) | Node::PowI(a, _) | Node::Call1(_, a) => a.visit(f),
            Node::Bin(_, a, b) | Node::Call2(_, a, b) => {
                a.visit(f);
                b.visit(f);
            }
            _ => {}
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::data::quantities;

    fn eval(text: &str, params: &[&str], p: &[f64]) -> f64 {
        let case = &crate::data::paper().cases[0];
        Expr::parse(text, params).unwrap().eval(p, case)
    }

    fn err(text: &str) -> ExprError {
        Expr::parse(text, &["k", "p"]).err().expect("an error")
    }

    #[test]
    fn arithmetic_follows_the_usual_precedence() {
        assert_eq!(eval("1 + 2 * 3", &[], &[]), 7.0);
        assert_eq!(eval("(1 + 2) * 3", &[], &[]), 9.0);
        assert_eq!(eval("-2^2", &[], &[]), -4.0);
        assert_eq!(eval("2^3^2", &[], &[]), 512.0);
        assert_eq!(eval("2^-1", &[], &[]), 0.5);
        assert_eq!(
            eval("k^2 + k^-2 + k^0.5", &["k"], &[4.0]),
            16.0 + 0.0625 + 2.0
        );
        assert_eq!(eval("(-2)^3", &[], &[]), -8.0);
        assert_eq!(eval("1/2", &[], &[]), 0.5);
        assert_eq!(eval("8 / 2 / 2", &[], &[]), 2.0);
        assert_eq!(eval("1 - 2 - 3", &[], &[]), -4.0);
        assert_eq!(eval("1.5e2 + .5 + 2E-1", &[], &[]), 150.7);
        assert_eq!(eval("min(3, max(1, 2)) + pow(2, 10)", &[], &[]), 1026.0);
        assert!((eval("ln(e) + log10(1000) + exp(0) + sqrt(16)", &[], &[]) - 9.0).abs() < 1e-15);
        assert!((eval("atan(1) * 4 - pi + tanh(0) + abs(-1)", &[], &[]) - 1.0).abs() < 1e-15);
        assert!((eval("sin(pi/2) + cos(0) + tan(0)", &[], &[]) - 2.0).abs() < 1e-15);
    }

    #[test]
    fn parameters_bind_by_position_and_quantities_read_the_case() {
        let case = &crate::data::paper().cases[0];
        assert_eq!(eval("1 + k * p", &["k", "p"], &[0.5, 4.0]), 3.0);
        let e = Expr::parse("k * shear_rate + wavelength_mm", &["k"]).unwrap();
        let shear = quantities::by_id("shear_rate").unwrap().of(case);
        assert_eq!(e.eval(&[2.0], case), 2.0 * shear + case.wavelength_mm);
        assert_eq!(e.params_used(), vec![0]);
        assert_eq!(e.quantities_used(), vec!["shear_rate", "wavelength_mm"]);
    }

    #[test]
    fn a_recorded_column_is_read_by_its_dotted_name() {
        let mut case = crate::data::paper().cases[0].clone();
        case.recorded.values.push(("temperature_c".into(), 30.0));
        let e = Expr::parse("k * (recorded.temperature_c / 25)^2", &["k"]).unwrap();
        assert!((e.eval(&[2.0], &case) - 2.0 * 1.44).abs() < 1e-12);
        assert!(e.eval(&[2.0], &crate::data::paper().cases[0]).is_nan());
        let Err(err) = Expr::parse("recorded.Temp + 1", &[]) else {
            panic!("an upper-case recorded name is not a name");
        };
        assert!(err.message.contains("recorded.NAME"), "{}", err.message);
        assert!(Expr::parse("wavelength_mm.x", &[]).is_err());
    }

    #[test]
    fn errors_give_the_column_and_what_is_allowed() {
        let e = err("1 + k * shear_rat");
        assert_eq!(e.column, 9);
        assert!(e.message.contains("`shear_rate`"), "{}", e.message);
        let e = err("1 + (k * 2");
        assert_eq!(e.column, 11);
        assert!(e.message.contains("close"), "{}", e.message);
        let e = err("k $ 2");
        assert_eq!((e.column, e.message.contains('$')), (3, true));
        let e = err("min(k)");
        assert!(
            e.column == 1 && e.message.contains("2 arguments"),
            "{}",
            e.message
        );
        let e = err("sqr(k)");
        assert!(e.message.contains("`sqrt`"), "{}", e.message);
        let e = err("k 2");
        assert_eq!(e.column, 3);
        let e = err("1 +");
        assert_eq!(e.column, 4);
        assert_eq!(err("").column, 1);
        assert!(err("exp + 1").message.contains("function"));
        assert!(err("2e").message.contains("`e`") || err("2e").column == 2);
    }
}
