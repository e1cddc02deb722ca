//! Reading effects files (docs/effects-format.md): TOML with one or more
//! `[[effect]]` tables, checked field by field, every error naming the file,
//! the effect, the field and the line and column (TOML spans; inside a
//! formula, the column of the offending character).

use super::expr::{is_reserved, suggest};
use super::formula::{FormulaEffect, UserEffectSpec, UserParam};
use super::place::Place;
use super::toml_position::{line_col, raw_offset};
use crate::data::limits::echo;
use crate::data::quantities;
use serde::Deserialize;
use std::collections::BTreeMap;
use std::ops::Range;
use toml::Spanned;

/// A problem in an effects file, with its position (`line` 0 when the
/// problem is the file itself).
#[derive(Debug, Clone, PartialEq)]
pub struct UserEffectError {
    pub file: String,
    /// The effect's name, when it is known at the error.
    pub effect: Option<String>,
    pub field: String,
    pub line: usize,
    pub column: usize,
    pub message: String,
}

impl std::fmt::Display for UserEffectError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}", self.file)?;
        if self.line > 0 {
            write!(f, ", line {}, column {}", self.line, self.column)?;
        }
        if let Some(e) = &self.effect {
            write!(f, ": effect `{}`", echo(e))?;
        }
        write!(f, ", field `{}`: {}", echo(&self.field), self.message)
    }
}

impl std::error::Error for UserEffectError {}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawFile {
    #[serde(default)]
    effect: Vec<RawEffect>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawEffect {
    name: Spanned<String>,
    statement: Spanned<String>,
    reference: Spanned<String>,
    applies_to: Option<String>,
    #[serde(default)]
    param: Vec<RawParam>,
    places: Spanned<BTreeMap<Spanned<String>, Spanned<String>>>,
    /// Effects it was fitted on top of (`NAME:k=v,...`), checked when a
    /// command applies them (a base may be defined later in the file).
    #[serde(default)]
    base: Vec<Spanned<String>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawParam {
    name: Spanned<String>,
    unit: String,
    default: Spanned<f64>,
    min: Spanned<f64>,
    max: Spanned<f64>,
    free: Option<bool>,
    doc: Option<String>,
}

struct Ctx<'a> {
    file: &'a str,
    text: &'a str,
}

impl Ctx<'_> {
    fn err(
        &self,
        effect: Option<&str>,
        field: &str,
        span: Range<usize>,
        msg: String,
    ) -> UserEffectError {
        let (line, column) = line_col(self.text, span.start);
        UserEffectError {
            file: self.file.to_string(),
            effect: effect.map(str::to_string),
            field: field.to_string(),
            line,
            column,
            message: msg,
        }
    }

    /// A TOML or schema error: find the effect it falls in and the field it names.
    fn toml_err(&self, e: &toml::de::Error) -> UserEffectError {
        let span = e.span().unwrap_or(0..0);
        let msg = e.message().trim().to_string();
        let start = span.start.min(self.text.len());
        let line_end = self.text[start..]
            .find('\n')
            .map_or(self.text.len(), |i| start + i);
        let line_start = self.text[..start].rfind('\n').map_or(0, |i| i + 1);
        // The field: named by the message, else the key of the line the error is on.
        let key = self.text[line_start..line_end]
            .split_once('=')
            .map(|(k, _)| k.trim().trim_matches('"').to_string())
            .filter(|k| !k.is_empty() && !k.starts_with('['));
        let field = msg
            .split('`')
            .nth(1)
            .filter(|_| msg.contains("field"))
            .map(str::to_string)
            .or(key)
            .unwrap_or_else(|| "(syntax)".to_string());
        // The effect whose `[[effect]]` header precedes (or is on) the error's line.
        let index = self.text[..line_end]
            .lines()
            .filter(|l| l.trim() == "[[effect]]")
            .count();
        let effect = self.text.parse::<toml::Table>().ok().and_then(|t| {
            let list = t.get("effect")?.as_array()?.clone();
            let e = list.get(index.checked_sub(1)?)?.clone();
            e.get("name")?.as_str().map(str::to_string)
        });
        let allowed = if msg.contains("unknown field") {
            ""
        } else if msg.contains("invalid type") {
            " (names, units, statements and formulas are strings; default, min, max numbers; free true/false)"
        } else {
            ""
        };
        self.err(effect.as_deref(), &field, span, format!("{msg}{allowed}"))
    }
}

/// Parse an effects file's text; `file` names it in messages.
pub fn parse(text: &str, file: &str) -> Result<Vec<UserEffectSpec>, UserEffectError> {
    let cx = Ctx { file, text };
    let raw: RawFile = toml::from_str(text).map_err(|e| cx.toml_err(&e))?;
    if raw.effect.is_empty() {
        return Err(cx.err(
            None,
            "effect",
            0..0,
            "no [[effect]] table; see docs/effects-format.md".into(),
        ));
    }
    let mut out: Vec<UserEffectSpec> = Vec::new();
    for e in raw.effect {
        if out.iter().any(|s| &s.name == e.name.get_ref()) {
            let name = e.name.get_ref();
            return Err(cx.err(
                Some(name),
                "name",
                e.name.span(),
                format!("effect `{name}` is defined twice in this file"),
            ));
        }
        let spec = check_effect(&cx, e)?;
        out.push(spec);
    }
    Ok(out)
}

fn is_kebab(s: &str) -> bool {
    s.starts_with(|c: char| c.is_ascii_lowercase())
        && s.chars()
            .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '-')
}

fn is_ident(s: &str) -> bool {
    s.starts_with(|c: char| c.is_ascii_lowercase())
        && s.chars()
            .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_')
}

fn check_effect(cx: &Ctx, e: RawEffect) -> Result<UserEffectSpec, UserEffectError> {
    let name = e.name.get_ref().clone();
    let at = |field: &str, span: Range<usize>, msg: String| cx.err(Some(&name), field, span, msg);
    check_identity(&e, &at)?;
    let mut params: Vec<UserParam> = Vec::new();
    for p in &e.param {
        let param = check_param(p, &params, &at)?;
        params.push(param);
    }
    let (mut places, used) = check_places(cx, &name, &e.places, &params)?;
    for b in &e.base {
        let head = b.get_ref().split(':').next().unwrap_or("").trim();
        if !is_kebab(head) {
            return Err(at(
                "base",
                b.span(),
                format!(
                    "`{}` is not an effect as the command line takes it: NAME or NAME:k=v,...",
                    b.get_ref()
                ),
            ));
        }
    }
    // One canonical order (the stages' order), whatever the file's: a written file reads back equal.
    places.sort_by_key(|(p, _)| *p);
    if let Some(i) = (0..params.len()).find(|&i| !used[i] && params[i].free) {
        let span = e.param[i].name.span();
        return Err(at(&format!("param.{}", params[i].name), span, format!("free parameter `{}` appears in no formula, so no data can determine it; use it or remove it", params[i].name)));
    }
    Ok(UserEffectSpec {
        name,
        statement: e.statement.into_inner(),
        reference: e.reference.into_inner(),
        applies_to: e.applies_to,
        params,
        places,
        base: e.base.into_iter().map(Spanned::into_inner).collect(),
    })
}

/// An error at a field of the effect being checked.
type At<'a> = dyn Fn(&str, Range<usize>, String) -> UserEffectError + 'a;

/// The name (kebab-case, not a catalogue effect's) and the two lines of
/// prose every effect must carry.
fn check_identity(e: &RawEffect, at: &At) -> Result<(), UserEffectError> {
    let name = e.name.get_ref();
    if !is_kebab(name) {
        return Err(at("name", e.name.span(), format!("`{}` is not kebab-case; allowed: a lowercase letter, then lowercase letters, digits and `-`", echo(name))));
    }
    if super::CATALOGUE.iter().any(|c| c.name() == name) {
        return Err(at("name", e.name.span(), format!("`{name}` is a catalogue effect; choose another name (`swimbot effects` lists the catalogue)")));
    }
    for (field, v) in [("statement", &e.statement), ("reference", &e.reference)] {
        if v.get_ref().trim().is_empty() {
            return Err(at(
                field,
                v.span(),
                format!(
                    "the {field} is empty; say the physics in one line and where it comes from"
                ),
            ));
        }
    }
    Ok(())
}

/// One parameter: a fresh identifier that names no case quantity, finite
/// bounds with `min < max`, and a default inside them.
fn check_param(p: &RawParam, before: &[UserParam], at: &At) -> Result<UserParam, UserEffectError> {
    let pname = p.name.get_ref();
    let field = format!("param.{pname}");
    if !is_ident(pname) {
        return Err(at("param.name", p.name.span(), format!("`{}` is not an identifier; allowed: a lowercase letter, then lowercase letters, digits and `_`", echo(pname))));
    }
    if quantities::by_id(pname).is_some() || is_reserved(pname) {
        return Err(at("param.name", p.name.span(), format!("`{pname}` is the name of a case quantity, constant or function; rename the parameter")));
    }
    if before.iter().any(|q| &q.name == pname) {
        return Err(at(
            "param.name",
            p.name.span(),
            format!("parameter `{pname}` is declared twice"),
        ));
    }
    for (what, v) in [("default", &p.default), ("min", &p.min), ("max", &p.max)] {
        if !v.get_ref().is_finite() {
            return Err(at(
                &format!("{field}.{what}"),
                v.span(),
                format!("{} is not a finite number", v.get_ref()),
            ));
        }
    }
    let (d, lo, hi) = (*p.default.get_ref(), *p.min.get_ref(), *p.max.get_ref());
    if lo >= hi {
        return Err(at(
            &format!("{field}.min"),
            p.min.span(),
            format!("min = {lo} must be below max = {hi}"),
        ));
    }
    if !(lo..=hi).contains(&d) {
        return Err(at(
            &format!("{field}.default"),
            p.default.span(),
            format!("default = {d} is outside [min, max] = [{lo}, {hi}]"),
        ));
    }
    Ok(UserParam {
        name: pname.clone(),
        unit: p.unit.clone(),
        default: d,
        min: lo,
        max: hi,
        free: p.free.unwrap_or(true),
        doc: p.doc.clone().unwrap_or_default(),
    })
}

/// The places table: each key a known place, each formula parsed over the
/// parameters; returns the places and which parameters some formula uses.
#[allow(clippy::type_complexity)]
fn check_places(
    cx: &Ctx,
    name: &str,
    table: &Spanned<BTreeMap<Spanned<String>, Spanned<String>>>,
    params: &[UserParam],
) -> Result<(Vec<(Place, String)>, Vec<bool>), UserEffectError> {
    let at = |field: &str, span: Range<usize>, msg: String| cx.err(Some(name), field, span, msg);
    if table.get_ref().is_empty() {
        return Err(at(
            "places",
            table.span(),
            format!(
                "the places table is empty; give at least one of: {}",
                place_list()
            ),
        ));
    }
    let names: Vec<&str> = params.iter().map(|p| p.name.as_str()).collect();
    let mut places = Vec::new();
    let mut used = vec![false; params.len()];
    for (key, formula) in table.get_ref() {
        let place = Place::from_name(key.get_ref()).ok_or_else(|| {
            at(
                "places",
                key.span(),
                format!(
                    "unknown place `{}`{}; places: {}",
                    echo(key.get_ref()),
                    suggest(key.get_ref(), Place::ALL.iter().map(|p| p.name())),
                    place_list()
                ),
            )
        })?;
        let field = format!("places.\"{}\"", place.name());
        let expr = super::expr::Expr::parse(formula.get_ref(), &names).map_err(|err| {
            // The column counts decoded characters; map it through the value's raw text.
            let span = formula.span();
            let raw = cx.text.get(span.clone()).unwrap_or_default();
            let s = span.start + raw_offset(raw, err.column - 1);
            at(
                &field,
                s..s,
                format!(
                    "formula `{}`, formula column {}: {}",
                    echo(formula.get_ref()),
                    err.column,
                    err.message
                ),
            )
        })?;
        for i in expr.params_used() {
            used[i] = true;
        }
        places.push((place, formula.get_ref().clone()));
    }
    Ok((places, used))
}

fn place_list() -> String {
    Place::ALL
        .iter()
        .map(|p| p.name())
        .collect::<Vec<_>>()
        .join(", ")
}

/// Read, check and compile an effects file, recorded in `inputs`.
pub fn load_file(
    path: &std::path::Path,
    inputs: &crate::provenance::Inputs,
) -> Result<Vec<FormulaEffect>, UserEffectError> {
    let file = path.display().to_string();
    let whole = |message: String| UserEffectError {
        file: file.clone(),
        effect: None,
        field: "(file)".into(),
        line: 0,
        column: 0,
        message,
    };
    let limit = crate::data::limits::MAX_EFFECT_FILE_BYTES;
    // Bounded while reading, even for a file that grows or a device without a size.
    let text = crate::input_file::read_text(path, limit, "an effects file")
        .map_err(|e| whole(e.to_string()))?;
    inputs.record(path, text.as_bytes());
    let specs = parse(&text, &file)?;
    specs
        .into_iter()
        .map(|s| {
            FormulaEffect::new(s, &file).map_err(|e| UserEffectError {
                file: file.clone(),
                effect: None,
                field: e.place.name().into(),
                line: 0,
                column: e.error.column,
                message: e.error.message,
            })
        })
        .collect()
}
