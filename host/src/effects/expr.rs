//! Formulas of user effects: a small arithmetic language compiled once into
//! a tree whose variables are bound by index, then evaluated per case.
//!
//! Grammar (usual precedence; `^` binds tighter than unary minus and is
//! right-associative, so `-x^2 = -(x^2)` and `2^-1 = 0.5`):
//!
//! ```text
//! sum     := product (("+" | "-") product)*
//! product := unary (("*" | "/") unary)*
//! unary   := ("-" | "+") unary | power
//! power   := atom ("^" unary)?
//! atom    := number | constant | parameter | quantity
//!          | function "(" sum ("," sum)* ")" | "(" sum ")"
//! ```
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
//! whole language is ~250 lines here, tested below, with exact positions.

pub use super::expr_lex::suggest;
use super::expr_lex::{lex, Kind, Token};
use crate::data::limits::{MAX_FORMULA_CHARS, MAX_FORMULA_DEPTH};
use crate::data::quantities::{self, Quantity};
use crate::data::Case;

/// A compiled formula.
#[derive(Clone)]
pub struct Expr {
    root: Node,
}

#[derive(Clone)]
enum Node {
    Num(f64),
    Param(usize),
    Quantity(&'static Quantity),
    Neg(Box<Node>),
    Bin(BinOp, Box<Node>, Box<Node>),
    /// `x^n` with a constant integer exponent: `powi` is exact and ~10x faster than `powf`.
    PowI(Box<Node>, i32),
    Call1(Fn1, Box<Node>),
    Call2(Fn2, Box<Node>, Box<Node>),
}

#[derive(Clone, Copy)]
enum BinOp {
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
    /// Formulas longer than [`MAX_FORMULA_CHARS`] or nested deeper than
    /// [`MAX_FORMULA_DEPTH`] are errors (the parser and the evaluator recurse
    /// per level; without the limits a long formula overflowed the stack).
    pub fn parse(text: &str, params: &[&str]) -> Result<Expr, ExprError> {
        let chars = text.chars().count();
        if chars > MAX_FORMULA_CHARS {
            return Err(ExprError {
                column: MAX_FORMULA_CHARS + 1,
                message: format!(
                    "the formula has {chars} characters; at most {MAX_FORMULA_CHARS} are allowed \
                     (split the law into parameters and a shorter formula)"
                ),
            });
        }
        let tokens = lex(text)?;
        let mut p = Parser {
            tokens,
            pos: 0,
            params,
            end_column: chars + 1,
            depth: 0,
        };
        if p.tokens.is_empty() {
            return Err(ExprError {
                column: 1,
                message: "the formula is empty".into(),
            });
        }
        let root = p.sum()?;
        if let Some(t) = p.tokens.get(p.pos) {
            return Err(ExprError {
                column: t.column,
                message: format!("unexpected `{}` after a complete expression", t.text),
            });
        }
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

struct Parser<'a> {
    tokens: Vec<Token>,
    pos: usize,
    params: &'a [&'a str],
    end_column: usize,
    /// Levels of `unary` open now: every nesting (parenthesis, call
    /// argument, sign, exponent) passes through it once.
    depth: usize,
}

impl Parser<'_> {
    fn peek_op(&self) -> Option<char> {
        match self.tokens.get(self.pos).map(|t| &t.kind) {
            Some(Kind::Op(c)) => Some(*c),
            _ => None,
        }
    }

    fn column(&self) -> usize {
        self.tokens
            .get(self.pos)
            .map_or(self.end_column, |t| t.column)
    }

    fn expect(&mut self, op: char, what: &str) -> Result<(), ExprError> {
        if self.peek_op() == Some(op) {
            self.pos += 1;
            return Ok(());
        }
        let found = self
            .tokens
            .get(self.pos)
            .map_or("the end of the formula".to_string(), |t| {
                format!("`{}`", t.text)
            });
        Err(ExprError {
            column: self.column(),
            message: format!("expected `{op}` {what}, found {found}"),
        })
    }

    fn sum(&mut self) -> Result<Node, ExprError> {
        let mut left = self.product()?;
        while let Some(op @ ('+' | '-')) = self.peek_op() {
            self.pos += 1;
            let right = self.product()?;
            let op = if op == '+' { BinOp::Add } else { BinOp::Sub };
            left = Node::Bin(op, Box::new(left), Box::new(right));
        }
        Ok(left)
    }

    fn product(&mut self) -> Result<Node, ExprError> {
        let mut left = self.unary()?;
        while let Some(op @ ('*' | '/')) = self.peek_op() {
            self.pos += 1;
            let right = self.unary()?;
            let op = if op == '*' { BinOp::Mul } else { BinOp::Div };
            left = Node::Bin(op, Box::new(left), Box::new(right));
        }
        Ok(left)
    }

    fn unary(&mut self) -> Result<Node, ExprError> {
        if self.depth >= MAX_FORMULA_DEPTH {
            return Err(ExprError {
                column: self.column(),
                message: format!(
                    "the formula nests deeper than {MAX_FORMULA_DEPTH} levels here \
                     (parentheses, calls, signs and powers inside one another)"
                ),
            });
        }
        self.depth += 1;
        let node = self.unary_at_depth();
        self.depth -= 1;
        node
    }

    fn unary_at_depth(&mut self) -> Result<Node, ExprError> {
        match self.peek_op() {
            Some('-') => {
                self.pos += 1;
                Ok(Node::Neg(Box::new(self.unary()?)))
            }
            Some('+') => {
                self.pos += 1;
                self.unary()
            }
            _ => self.power(),
        }
    }

    fn power(&mut self) -> Result<Node, ExprError> {
        let base = self.atom()?;
        if self.peek_op() == Some('^') {
            self.pos += 1;
            let exponent = self.unary()?;
            let small_int = |x: f64| x.fract() == 0.0 && x.abs() <= 64.0;
            return Ok(match exponent {
                Node::Num(x) if small_int(x) => Node::PowI(Box::new(base), x as i32),
                Node::Neg(ref inner) => match **inner {
                    Node::Num(x) if small_int(x) => Node::PowI(Box::new(base), -(x as i32)),
                    _ => Node::Bin(BinOp::Pow, Box::new(base), Box::new(exponent)),
                },
                _ => Node::Bin(BinOp::Pow, Box::new(base), Box::new(exponent)),
            });
        }
        Ok(base)
    }

    fn atom(&mut self) -> Result<Node, ExprError> {
        let Some(t) = self.tokens.get(self.pos).cloned() else {
            return Err(ExprError {
                column: self.end_column,
                message: "the formula ends where a value was expected".into(),
            });
        };
        self.pos += 1;
        match t.kind {
            Kind::Num(x) => Ok(Node::Num(x)),
            Kind::Op('(') => {
                let inner = self.sum()?;
                self.expect(')', &format!("to close the `(` at column {}", t.column))?;
                Ok(inner)
            }
            Kind::Op(_) => Err(ExprError {
                column: t.column,
                message: format!("expected a value, found `{}`", t.text),
            }),
            Kind::Ident if self.peek_op() == Some('(') => self.call(&t),
            Kind::Ident => self.name(&t),
        }
    }

    fn call(&mut self, t: &Token) -> Result<Node, ExprError> {
        self.pos += 1;
        let mut args = vec![self.sum()?];
        while self.peek_op() == Some(',') {
            self.pos += 1;
            args.push(self.sum()?);
        }
        self.expect(')', &format!("to close the call of `{}`", t.text))?;
        let name = t.text.as_str();
        let arity = |n: usize| ExprError {
            column: t.column,
            message: format!(
                "`{name}` takes {n} argument{}, got {}",
                if n == 1 { "" } else { "s" },
                args.len()
            ),
        };
        if let Some((_, f)) = FUNCTIONS_1.iter().find(|f| f.0 == name) {
            if args.len() != 1 {
                return Err(arity(1));
            }
            return Ok(Node::Call1(*f, Box::new(args.remove(0))));
        }
        if let Some((_, f)) = FUNCTIONS_2.iter().find(|f| f.0 == name) {
            if args.len() != 2 {
                return Err(arity(2));
            }
            let b = args.pop().expect("two arguments");
            let a = args.pop().expect("two arguments");
            return Ok(Node::Call2(*f, Box::new(a), Box::new(b)));
        }
        let known: Vec<&str> = FUNCTIONS_1
            .iter()
            .map(|f| f.0)
            .chain(FUNCTIONS_2.iter().map(|f| f.0))
            .collect();
        Err(ExprError {
            column: t.column,
            message: format!(
                "unknown function `{name}`{}; functions: {}",
                suggest(name, known.iter().copied()),
                known.join(", ")
            ),
        })
    }

    fn name(&mut self, t: &Token) -> Result<Node, ExprError> {
        let name = t.text.as_str();
        if let Some(i) = self.params.iter().position(|p| *p == name) {
            return Ok(Node::Param(i));
        }
        if let Some((_, x)) = CONSTANTS.iter().find(|c| c.0 == name) {
            return Ok(Node::Num(*x));
        }
        if let Some(q) = quantities::by_id(name) {
            return Ok(Node::Quantity(q));
        }
        let message = if is_reserved(name) {
            format!("`{name}` is a function: write `{name}(...)`")
        } else {
            let candidates = self
                .params
                .iter()
                .copied()
                .chain(CONSTANTS.iter().map(|c| c.0))
                .chain(quantities::FEATURES.iter().map(|q| q.id))
                .chain(quantities::FIELDS.iter().map(|q| q.id));
            format!(
                "unknown name `{name}`{}; a name is one of the effect's parameters ({}), \
                 pi, e, or a case quantity (`swimbot effects --quantities` lists them)",
                suggest(name, candidates),
                if self.params.is_empty() {
                    "none".to_string()
                } else {
                    self.params.join(", ")
                }
            )
        };
        Err(ExprError {
            column: t.column,
            message,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
