//! What `diagnose` said of the study's model at one moment, kept in the
//! study: the verdict, its note, and what it proposed to add (catalogue
//! effects by name, located laws as `place = formula` with the name
//! `diagnose --write-effect` gives them). The page shows the first
//! diagnosis, the one that proposed each step, and the final one, from
//! these records.

use crate::data::Dataset;
use crate::model::Model;
use crate::workbench::diagnose::{diagnose, DiagnoseSettings, Diagnosis, VerdictKind};
use crate::workbench::discovery::write::written_names;
use crate::workbench::fit::FitError;
use crate::workbench::headline::{headline, Headline};
use crate::workbench::robust::Likelihood;
use serde::{Deserialize, Serialize};

/// One thing a diagnosis proposes to add.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Proposal {
    /// The catalogue effect, or the name `--write-effect` gives the law.
    pub name: String,
    /// `place = formula`, for a located law.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub law: Option<String>,
    /// In words, with its fitted values.
    pub text: String,
    /// Share of the excess chi-square (above the noise floor) it removes.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub explains: Option<f64>,
}

/// A diagnosis, as the study keeps it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DiagnosisRecord {
    /// `none-needed`, `identified`, `located`, `indistinguishable`, `unexplained`.
    pub verdict: String,
    /// The verdict in words.
    pub note: String,
    #[serde(default, rename = "proposal", skip_serializing_if = "Vec::is_empty")]
    pub proposals: Vec<Proposal>,
    /// The answer's numbers, as `diagnose --format json` prints them under
    /// `headline` (absent from study files written before it was kept).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub headline: Option<Headline>,
}

impl DiagnosisRecord {
    /// Keep what the study needs of `d`: its headline, and the proposals
    /// read off the headline's steps (the verdict's found set, each with
    /// the share of the excess chi-square the headline gives it), so that
    /// the page, the terminal and the JSON name the same effects with the
    /// same numbers.
    pub fn of(d: &Diagnosis) -> Self {
        let headline = headline(d, None);
        let mut proposals = Vec::new();
        if d.verdict.kind != VerdictKind::NoneNeeded {
            // Each law by the name the written file gives it, and only the
            // laws written: a proposal is added from that file.
            let written = d.laws_to_write();
            let names = written_names(&written);
            let mut located = d.verdict.located.iter();
            for st in &headline.steps {
                let law = match st.kind.as_ref() {
                    "located" => Some(located.next()),
                    _ => None,
                };
                let proposal = match law {
                    Some(Some(l)) => {
                        let Some(i) = written
                            .iter()
                            .position(|w| w.place == l.place && w.formula == l.formula)
                        else {
                            continue;
                        };
                        Proposal {
                            name: names[i].clone(),
                            law: Some(format!("{} = {}", l.place, l.formula)),
                            text: format!("{}: {}", l.describe(), l.interpretation),
                            explains: st.explains,
                        }
                    }
                    Some(None) => continue,
                    None => Proposal {
                        name: st.law.clone(),
                        law: None,
                        text: format!("the catalogue effect {}", st.law),
                        explains: st.explains,
                    },
                };
                proposals.push(proposal);
            }
        }
        DiagnosisRecord {
            verdict: d.verdict.kind.name().to_string(),
            note: d.verdict.note.clone(),
            proposals,
            headline: Some(headline),
        }
    }

    /// Diagnose `model` on `data` with the study's likelihood.
    pub fn run(model: &Model, data: &Dataset, likelihood: Likelihood) -> Result<Self, FitError> {
        let settings = DiagnoseSettings {
            likelihood,
            ..DiagnoseSettings::default()
        };
        let d = diagnose(model, data, &settings)?;
        Ok(Self::of(&d))
    }

    /// The proposal an added effect answers: the same name, or for a user
    /// effect the same law at the same place.
    pub fn proposal_for(&self, name: &str, formula: &[String]) -> Option<&Proposal> {
        self.proposals.iter().find(|p| {
            p.name == name
                || (p.law.is_none() && p.name.split(" + ").any(|part| part == name))
                || p.law
                    .as_ref()
                    .is_some_and(|l| formula.iter().any(|f| f == l))
        })
    }
}

impl Proposal {
    /// The commands that add what it proposes, in order: a located law is
    /// written by `diagnose --write-effect` and added from the file; a
    /// set of catalogue effects (`a + b`) is added one step at a time,
    /// since a step is one effect.
    pub fn add_commands(&self) -> Vec<String> {
        match &self.law {
            Some(_) => vec![
                "swimbot diagnose --write-effect found.toml".into(),
                format!("swimbot add found.toml#{}", self.name),
            ],
            None => self
                .name
                .split(" + ")
                .map(|e| format!("swimbot add {e}"))
                .collect(),
        }
    }
}
