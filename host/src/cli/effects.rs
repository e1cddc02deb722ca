//! `swimbot effects`: the catalogue of physical effects, the user effects
//! loaded with `--effect-file FILE.toml` (with their formulas and file), and,
//! with `--quantities`, the case quantities a formula may use.

use super::model_args::EffectFiles;
use super::output::{print_json, TableOrJson};
use super::CliError;
use crate::data::model_quantities::MODEL_QUANTITIES;
use crate::data::quantities::{FEATURES, FIELDS};
use crate::format::{fmt_trim, with_unit};
use crate::provenance::Inputs;
use clap::Args;

#[derive(Args, Debug)]
pub struct EffectsArgs {
    #[arg(long, value_enum, default_value = "table", help = super::output::FORMAT_HELP)]
    pub format: TableOrJson,
    #[command(flatten)]
    pub effect_files: EffectFiles,
    /// List the case quantities (features, fields and the model's own
    /// quantities, which a formula reads from the effects beneath it)
    /// usable in formulas instead.
    #[arg(long)]
    pub quantities: bool,
}

#[derive(serde::Serialize)]
struct Entry<'a> {
    name: &'a str,
    statement: &'a str,
    reference: &'a str,
    applies_to: &'a str,
    params: &'a [crate::effects::ParamSpec],
    /// "catalogue" or the effects file it came from.
    source: String,
    /// Place -> formula, for user effects.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    formulas: Vec<(String, String)>,
}

#[derive(serde::Serialize)]
struct QuantityEntry {
    id: &'static str,
    name: &'static str,
    unit: &'static str,
    kind: &'static str,
    doc: &'static str,
}

fn quantities(format: TableOrJson, inputs: &Inputs) {
    let entries: Vec<QuantityEntry> = FEATURES
        .iter()
        .map(|q| (q, "feature"))
        .chain(FIELDS.iter().map(|q| (q, "field")))
        .chain(MODEL_QUANTITIES.iter().map(|q| (q, "model")))
        .map(|(q, kind)| QuantityEntry {
            id: q.id,
            name: q.name,
            unit: q.unit,
            kind,
            doc: q.doc,
        })
        .collect();
    if format == TableOrJson::Json {
        print_json(&entries, inputs);
        return;
    }
    for q in &entries {
        println!(
            "{:<20} {:<8} {:<30} {:<7} {}",
            q.id,
            q.kind,
            q.name,
            with_unit("", q.unit).trim(),
            q.doc
        );
    }
}

pub fn run(args: EffectsArgs, inputs: &Inputs) -> Result<(), CliError> {
    let catalogue = args.effect_files.load(inputs)?;
    if args.quantities {
        quantities(args.format, inputs);
        return Ok(());
    }
    let all = catalogue.all();
    let entries: Vec<Entry> = all
        .iter()
        .map(|e| {
            let u = e.as_formula();
            Entry {
                name: e.name(),
                statement: e.statement(),
                reference: e.reference(),
                applies_to: e.applicability(),
                params: e.params(),
                source: u.map_or("catalogue".to_string(), |u| u.source().to_string()),
                formulas: u.map_or(Vec::new(), |u| {
                    u.spec()
                        .places
                        .iter()
                        .map(|(p, f)| (p.name().to_string(), f.clone()))
                        .collect()
                }),
            }
        })
        .collect();
    if args.format == TableOrJson::Json {
        print_json(&entries, inputs);
        return Ok(());
    }
    for e in &entries {
        println!(
            "{}\n  {}\n  applies to: {}\n  reference:  {}",
            e.name, e.statement, e.applies_to, e.reference
        );
        if e.source != "catalogue" {
            println!("  from:       {}", e.source);
        }
        for (place, formula) in &e.formulas {
            println!("  {place:<15} = {formula}");
        }
        if e.params.is_empty() {
            println!("  parameters: none (fixed by physics)");
        }
        for p in e.params {
            // Defaults and bounds are settings: trimmed, not padded with zeros.
            let unit = with_unit("", &p.unit);
            println!(
                "  param {:<18} default {:>6} in [{}, {}]{:<4} {}{}",
                p.name,
                fmt_trim(p.default, 3),
                fmt_trim(p.min, 3),
                fmt_trim(p.max, 3),
                unit,
                if p.free { "" } else { "(fixed) " },
                p.doc
            );
        }
        println!();
    }
    Ok(())
}
