//! `swimbot effects`: the catalogue of physical effects.

use super::output::{print_json, Format};
use super::CliError;
use crate::effects::CATALOGUE;
use crate::report::fmt_sig;
use clap::Args;

#[derive(Args, Debug)]
pub struct EffectsArgs {
    #[arg(long, value_enum, default_value = "table")]
    pub format: Format,
}

#[derive(serde::Serialize)]
struct Entry {
    name: &'static str,
    statement: &'static str,
    reference: &'static str,
    applies_to: &'static str,
    params: &'static [crate::effects::ParamSpec],
}

pub fn run(args: EffectsArgs) -> Result<(), CliError> {
    let entries: Vec<Entry> = CATALOGUE
        .iter()
        .map(|e| Entry {
            name: e.name(),
            statement: e.statement(),
            reference: e.reference(),
            applies_to: e.applicability(),
            params: e.params(),
        })
        .collect();
    if args.format == Format::Json {
        print_json(&entries);
        return Ok(());
    }
    for e in &entries {
        println!(
            "{}\n  {}\n  applies to: {}\n  reference:  {}",
            e.name, e.statement, e.applies_to, e.reference
        );
        if e.params.is_empty() {
            println!("  parameters: none (fixed by physics)");
        }
        for p in e.params {
            println!(
                "  param {:<18} default {:>6} in [{}, {}] {:<3} {}{}",
                p.name,
                fmt_sig(p.default, 3),
                fmt_sig(p.min, 3),
                fmt_sig(p.max, 3),
                p.unit,
                if p.free { "" } else { "(fixed) " },
                p.doc
            );
        }
        println!();
    }
    Ok(())
}
