//! Output formats shared by the subcommands.

use clap::ValueEnum;

#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    Table,
    Json,
    Csv,
}

/// Print JSON to stdout (serialisation of our own types cannot fail).
pub fn print_json<T: serde::Serialize>(value: &T) {
    println!(
        "{}",
        serde_json::to_string_pretty(value).expect("serialisable")
    );
}

/// `Some(x)` formatted to `sig` digits, `-` for none.
pub fn opt(v: Option<f64>, sig: usize) -> String {
    v.map(|x| crate::report::fmt_sig(x, sig))
        .unwrap_or_else(|| "-".into())
}

/// A relative error as a signed percentage.
pub fn pct(v: Option<f64>) -> String {
    v.map(|x| format!("{:+.1} %", 100.0 * x))
        .unwrap_or_else(|| "-".into())
}
