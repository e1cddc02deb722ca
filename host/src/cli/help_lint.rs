//! A lint over the real command tree: every argument has help text, an
//! argument whose name carries a unit (`--wavelength-mm`) names that unit
//! in its help, and an optional value without a default says what happens
//! when it is absent. Help is the CLI's only documentation at the prompt,
//! so a flag without it is a bug.

#[cfg(test)]
mod tests {
    use crate::cli::Cli;
    use clap::{ArgAction, CommandFactory};

    /// Name suffix -> the unit's spellings accepted in the help (whole words).
    const UNITS: &[(&str, &[&str])] = &[
        ("-pa-s", &["Pa s"]),
        ("-mm", &["mm"]),
        ("-hz", &["Hz"]),
        ("-gb", &["GB"]),
        ("-mn", &["mN"]),
        ("-s", &["s", "seconds"]),
    ];

    fn has_word(text: &str, word: &str) -> bool {
        text.match_indices(word).any(|(i, _)| {
            let before = text[..i].chars().next_back();
            let after = text[i + word.len()..].chars().next();
            !before.is_some_and(char::is_alphanumeric) && !after.is_some_and(char::is_alphanumeric)
        })
    }

    /// Every problem of one command and its subcommands, as `cmd --flag: why`.
    fn problems(cmd: &clap::Command, path: &str, out: &mut Vec<String>) {
        for arg in cmd.get_arguments() {
            let id = arg.get_id().as_str();
            if id == "help" || id == "version" {
                continue;
            }
            let name = arg.get_long().map_or(id.to_string(), |l| format!("--{l}"));
            let help = arg
                .get_help()
                .or(arg.get_long_help())
                .map(|h| h.to_string())
                .unwrap_or_default();
            if help.trim().is_empty() {
                out.push(format!("{path} {name}: no help text"));
                continue;
            }
            if let Some((suffix, spellings)) = UNITS.iter().find(|(s, _)| name.ends_with(s)) {
                if !spellings.iter().any(|u| has_word(&help, u)) {
                    out.push(format!(
                        "{path} {name}: the help does not state the unit ({suffix}: one of {spellings:?})"
                    ));
                }
            }
            let takes_value = matches!(arg.get_action(), ArgAction::Set);
            let lower = help.to_lowercase();
            if takes_value
                && !arg.is_required_set()
                && arg.get_default_values().is_empty()
                && !["default", "absent", "none", "if not given", "without it"]
                    .iter()
                    .any(|w| lower.contains(w))
            {
                out.push(format!(
                    "{path} {name}: optional, no default, and the help does not say what happens without it"
                ));
            }
        }
        for sub in cmd.get_subcommands() {
            problems(sub, &format!("{path} {}", sub.get_name()), out);
        }
    }

    #[test]
    fn every_argument_has_help_with_its_unit_and_default() {
        let cmd = Cli::command();
        cmd.clone().debug_assert();
        let mut out = Vec::new();
        problems(&cmd, "swimbot", &mut out);
        assert!(
            out.is_empty(),
            "{} help problems:\n{}",
            out.len(),
            out.join("\n")
        );
    }

    #[test]
    fn the_lint_catches_what_it_claims_to() {
        let bad = clap::Command::new("t")
            .arg(clap::Arg::new("a").long("wavelength-mm"))
            .arg(clap::Arg::new("b").long("time-s").help("how long"))
            .arg(
                clap::Arg::new("c")
                    .long("rate-hz")
                    .help("the rate (Hz), default 1"),
            )
            .arg(
                clap::Arg::new("d")
                    .long("gas-s")
                    .help("in seconds, default 2"),
            );
        let mut out = Vec::new();
        problems(&bad, "t", &mut out);
        assert_eq!(out.len(), 3, "{out:#?}");
        assert!(out[0].contains("--wavelength-mm: no help text"));
        assert!(out[1].contains("--time-s: the help does not state the unit"));
        assert!(out[2].contains("--time-s: optional, no default"));
    }
}
