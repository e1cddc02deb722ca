//! `swimbot convert`: a dataset from CSV to TOML or back, losslessly: the
//! file is validated first, then its setup block, raw trials and input
//! uncertainties are carried over as written (src/data/csv_write.rs), and
//! the written file opens with its provenance as `#` comments.

use super::CliError;
use crate::data::{convert_file_with, FileFormat, ReadOptions};
use crate::provenance::Inputs;
use clap::{Args, ValueEnum};
use std::path::PathBuf;

#[derive(Args, Debug)]
pub struct ConvertArgs {
    /// The dataset to convert (.csv is read as CSV, anything else as TOML).
    #[arg(value_name = "FILE")]
    pub input: PathBuf,
    /// The converted dataset [default: stdout].
    #[arg(short, long, value_name = "FILE")]
    pub output: Option<PathBuf>,
    /// Format to write [default: from the output's extension, else the other one of the input's].
    #[arg(long, value_enum)]
    pub to: Option<ToArg>,
    /// The CSV writes numbers with a decimal comma (0,586) [default: detected from the cells].
    #[arg(long)]
    pub decimal_comma: bool,
}

#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum ToArg {
    /// One row per case or per trial, the setup in a `# key = value` header.
    Csv,
    /// The TOML format of docs/data-format.md.
    Toml,
}

pub fn run(a: ConvertArgs, inputs: &Inputs) -> Result<(), CliError> {
    let to = match (a.to, &a.output) {
        (Some(ToArg::Csv), _) => FileFormat::Csv,
        (Some(ToArg::Toml), _) => FileFormat::Toml,
        (None, Some(out)) if out.extension().is_some() => FileFormat::of(out),
        (None, _) => match FileFormat::of(&a.input) {
            FileFormat::Csv => FileFormat::Toml,
            FileFormat::Toml => FileFormat::Csv,
        },
    };
    if let Some(out) = &a.output {
        super::output::check_output_file(out, inputs)?;
        if out.extension().is_some() && FileFormat::of(out) != to {
            return Err(CliError::input(format!(
                "--output {}: the extension says {}, --to says {}",
                out.display(),
                name(FileFormat::of(out)),
                name(to)
            )));
        }
    }
    let options = ReadOptions {
        decimal_comma: a.decimal_comma,
    };
    let body = convert_file_with(&a.input, to, &options, inputs)?;
    let text = crate::provenance::Provenance::capture(inputs).comment_block() + &body;
    match &a.output {
        Some(out) => super::output::write_atomically(out, text.as_bytes(), inputs),
        None => {
            print!("{text}");
            Ok(())
        }
    }
}

fn name(f: FileFormat) -> &'static str {
    match f {
        FileFormat::Csv => "csv",
        FileFormat::Toml => "toml",
    }
}
