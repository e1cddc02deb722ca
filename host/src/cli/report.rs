//! `swimbot report`: the HTML report with the diagnosis and its proposal
//! in the "error falls" chart.

use super::model_args::{DataArgs, ModelArgs};
use super::CliError;
use crate::workbench::diagnose::{diagnose, DiagnoseSettings};
use clap::Args;
use std::path::PathBuf;

#[derive(Args, Debug)]
pub struct ReportArgs {
    #[command(flatten)]
    pub data: DataArgs,
    #[command(flatten)]
    pub model: ModelArgs,
    /// Output directory (index.html is written there).
    #[arg(short, long, default_value = "report")]
    pub output: PathBuf,
}

pub fn run(a: ReportArgs) -> Result<(), CliError> {
    let data = a.data.load()?;
    let model = a.model.model()?;
    super::output::check_output_dir(&a.output)?;
    let d = diagnose(&model, &data, &DiagnoseSettings::default()).map_err(CliError::input)?;
    let path = crate::report::write_report(&a.output, &model, &data, Some(&d)).map_err(|e| {
        CliError::input(format!("writing the report to {}: {e}", a.output.display()))
    })?;
    println!("{}", path.display());
    Ok(())
}
