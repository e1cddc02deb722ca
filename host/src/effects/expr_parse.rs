//! The parser of user effects' formulas ([`super::expr`]): tokens
//! ([`super::expr_lex`]) to the tree that is evaluated, by recursive
//! descent, with the column of every error and the close matches of an
//! unknown name.
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

use super::expr::{is_reserved, suggest};
use super::expr::{BinOp, ExprError, Node, CONSTANTS, FUNCTIONS_1, FUNCTIONS_2};
use super::expr_lex::{lex, Kind, Token};
use crate::data::limits::{MAX_FORMULA_CHARS, MAX_FORMULA_DEPTH};
use crate::data::quantities;
use crate::data::Feature;

/// `text` compiled to a tree; identifiers resolve to `params` (by
/// position), then constants, then case quantities.
pub(super) fn parse(text: &str, params: &[&str]) -> Result<Node, ExprError> {
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
    Ok(root)
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
        if let Some(column) = name.strip_prefix(crate::data::feature::RECORDED_PREFIX) {
            if let Some(Feature::Recorded(n)) = Feature::recorded(column) {
                return Ok(Node::Recorded(n));
            }
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
                 pi, e, a case quantity (`swimbot effects --quantities` lists them) \
                 or a recorded column as `recorded.NAME`",
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
