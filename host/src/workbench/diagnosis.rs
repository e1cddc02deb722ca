//! What `diagnose` returns: the baseline, the catalogue's candidates, the
//! searches and the graded verdict with its steps, as plain data that the
//! commands and the page print (see [`super::diagnose`] for the method).

use super::compare::Comparison;
use super::data_quality::DataQuality;
use super::discovery::{Discovery, DiscoverySettings, Located};
use super::experiments::separation::Suggestion;
use super::features::Trend;
use super::fit::Estimate;
use super::score::FitScore;
use crate::model::Model;
use serde::Serialize;

/// Settings of [`super::diagnose::diagnose`]; `Default` gives the documented values.
#[derive(Debug, Clone)]
pub struct DiagnoseSettings {
    /// Quantile of the perfect model's chi-square that counts as "at the noise floor" (0.95).
    pub level: f64,
    /// AICc margin that makes a winner clear (4).
    pub clear_margin: f64,
    /// Try pairs when no single effect reaches the floor (true).
    pub second_effect: bool,
    /// Also try effects marked costly (false).
    pub include_costly: bool,
    /// Search beyond the catalogue (true).
    pub discover: bool,
    pub discovery: DiscoverySettings,
    /// The search over sets of laws and effects ([`super::search`]).
    pub search: super::search::settings::SearchSettings,
    /// Told as each of the [`DIAGNOSE_STAGES`] starts (progress display).
    pub progress: Option<super::progress::Progress>,
    /// The likelihood every fit of the diagnosis minimises (Gaussian: least
    /// squares); passed to each fit, never kept in a thread.
    pub likelihood: super::robust::Likelihood,
    /// The effects the diagnosis may propose: the compiled-in ones and the
    /// user effects this command or call loaded (compiled-in only).
    pub catalogue: crate::effects::Catalogue,
}

/// The diagnosis's stages: 1 is the data's quality and the base model's
/// comparison, then the searches (`workbench::diagnose`).
pub const DIAGNOSE_STAGES: u64 = 6;

impl Default for DiagnoseSettings {
    fn default() -> Self {
        DiagnoseSettings {
            level: 0.95,
            clear_margin: 4.0,
            second_effect: true,
            include_costly: false,
            discover: true,
            discovery: DiscoverySettings::default(),
            search: Default::default(),
            progress: None,
            likelihood: super::robust::Likelihood::Gaussian,
            catalogue: crate::effects::Catalogue::builtin(),
        }
    }
}

#[derive(Debug, Clone, Serialize)]
pub struct Baseline {
    pub model: String,
    pub mare: f64,
    pub max_abs_rel_err: f64,
    pub chi2: f64,
    pub chi2_reduced: Option<f64>,
    /// The reduced chi-square a perfect model stays below at `level`.
    pub noise_floor_chi2_reduced: Option<f64>,
    pub at_noise_floor: bool,
    /// The Student-t deviance of the residuals ([`super::robust`]).
    pub t_deviance: f64,
}

/// One model variant: the base plus one or two effects, fitted.
#[derive(Debug, Clone, Serialize)]
pub struct Candidate {
    pub effect: String,
    pub params: Vec<Estimate>,
    #[serde(flatten)]
    pub score: FitScore,
    pub non_identifiable: Vec<String>,
    pub converged: bool,
    #[serde(skip)]
    pub model: Model,
}

#[derive(Debug, Clone, Serialize)]
pub struct Verdict {
    /// The missing effect(s), `None` for "none needed", "indistinguishable" or "unexplained".
    pub effect: Option<String>,
    /// Some model variant fits to the noise floor.
    pub explained: bool,
    pub kind: VerdictKind,
    pub note: String,
    pub indistinguishable: Vec<String>,
    pub suggestion: Option<Suggestion>,
    /// Share of the excess chi-square (above the noise floor) the named
    /// catalogue effect(s) remove.
    pub effect_explained_fraction: Option<f64>,
    /// Located corrections: for `located` the finding, for `identified` the
    /// remainder beyond the named effect (if any), for `indistinguishable`
    /// the rivals, for `unexplained` the partial corrections that remove at
    /// least half of the excess and lower MARE. Never the same place,
    /// feature and form twice.
    pub located: Vec<Located>,
    /// The found set's members in order, each with the model beneath
    /// it (`on_top_of`); empty when nothing is needed or nothing is found.
    pub steps: Vec<SetMember>,
    /// For a set of two steps or more: what its joint fit fixes only
    /// together (parameters of different steps that trade, places with two
    /// laws, strengths whose interval spans no effect; `null` otherwise).
    pub joint: Option<super::search::joint::JointReading>,
    /// The sets of laws and effects the data cannot tell apart (a model
    /// confidence set, `super::search::rivals`): the found set first,
    /// then every other set at other places whose key is within the AICc
    /// margin of it (and at the noise floor when it is); empty when one set
    /// stands alone.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub sets: Vec<ExplainingSet>,
    /// For an `indistinguishable` verdict of several sets: the places every
    /// set has, stated as found.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub agreed_places: Vec<String>,
    /// For several sets: the key margin they were judged by, and the
    /// bootstrap that calibrated it (`workbench/search/calibrate.rs`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sets_margin: Option<SetsMargin>,
    /// How often the search picks each located term again when the cases
    /// are resampled (stability selection); empty when it was not measured.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub stability: Vec<TermStability>,
}

/// How often a located term is chosen again on resampled cases: stability
/// selection (Meinshausen & Buehlmann 2010, J. R. Stat. Soc. B 72, 417),
/// the ensembling of sparse regression as PySINDy does it. A term chosen
/// on few resamples is not located, however well the full data fit it.
#[derive(Debug, Clone, PartialEq, Serialize, serde::Deserialize)]
pub struct TermStability {
    /// The term as [`ExplainingSet::members`] and [`SetMember::name`] name it.
    pub term: String,
    /// `bootstrap` or `leave-one-out`.
    pub method: std::borrow::Cow<'static, str>,
    /// Resampled data sets searched.
    pub resamples: usize,
    /// Resamples whose chosen set holds the term.
    pub selected: usize,
    /// `selected / resamples`.
    pub fraction: f64,
}

/// The margin of the sets the data cannot tell apart, as `diagnose`
/// reports it (JSON `verdict.sets_margin`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SetsMargin {
    /// Keys within this of the chosen set's are not told apart.
    pub value: f64,
    /// The 95 % quantile of how far a wrong set beat the chosen set on
    /// data drawn from the chosen set's fit; `None` for the fixed margin.
    pub bootstrap_quantile: Option<f64>,
    /// Data sets drawn (0 for the fixed margin).
    pub draws: usize,
    /// Sets refitted on each draw, the chosen set included.
    pub candidates: usize,
}

/// One set of a model confidence set ([`Verdict::sets`]).
#[derive(Debug, Clone, Serialize)]
pub struct ExplainingSet {
    /// Each member: the law `place = formula (values)` or the catalogue
    /// effect's name.
    pub members: Vec<String>,
    /// The places (and catalogue names) of its members, sorted.
    pub places: Vec<String>,
    /// Its key (`AICc + sum 2 ln M`) minus the found set's (0 for the found
    /// set itself).
    pub key_difference: f64,
    pub at_noise_floor: bool,
    /// The measurement that best tells it from the found set, inside the
    /// rig (`None` for the found set itself).
    pub suggestion: Option<Suggestion>,
    /// Its Akaike weight among the stated sets, `exp(-d/2) / sum exp(-d/2)`
    /// over their key differences `d` (Burnham & Anderson 2002, sec. 2.9):
    /// the weight of evidence that it is the best of them.
    pub akaike_weight: f64,
    /// The starting model with the set at its joint fit (what `plan`
    /// separates); not serialised.
    #[serde(skip)]
    pub model: Option<Model>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum VerdictKind {
    NoneNeeded,
    Identified,
    Located,
    Indistinguishable,
    Unexplained,
}

impl VerdictKind {
    /// The kind as printed and in JSON (`none-needed`, ...).
    pub fn name(self) -> &'static str {
        match self {
            VerdictKind::NoneNeeded => "none-needed",
            VerdictKind::Identified => "identified",
            VerdictKind::Located => "located",
            VerdictKind::Indistinguishable => "indistinguishable",
            VerdictKind::Unexplained => "unexplained",
        }
    }
}

/// One member of the found set, in order: a catalogue effect or a
/// located law, fitted on top of the steps before it.
#[derive(Debug, Clone, Serialize)]
pub struct SetMember {
    /// `catalogue` or `located`.
    pub kind: &'static str,
    /// The catalogue effect's name, or the law `place = formula (values)`.
    pub name: String,
    /// The effects beneath it (`NAME:k=v,...`, the model `diagnose` was
    /// given first): what it was fitted on top of, machine-readable.
    pub on_top_of: Vec<String>,
    pub mare: f64,
    pub cv_mare: f64,
    pub chi2_reduced: Option<f64>,
    /// The deviance its fit minimised when it is not the chi-square
    /// ([`super::score::FitScore::deviance`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub deviance: Option<f64>,
    /// AICc of the minimised deviance ([`super::score`]).
    pub aicc: Option<f64>,
    pub at_noise_floor: bool,
    /// Share of the excess chi-square left by the steps before that this
    /// step removes.
    pub explained_fraction: Option<f64>,
}

#[derive(Debug, Clone, Serialize)]
pub struct Diagnosis {
    pub baseline: Baseline,
    pub comparison: Comparison,
    pub trends: Vec<Trend>,
    pub ranking: Vec<Candidate>,
    pub pairs: Vec<Candidate>,
    /// The search beyond the catalogue on the model as given.
    pub discovery: Option<Discovery>,
    /// The search on top of the catalogue effect that explains most, when
    /// one explains most but not all of the excess.
    pub remainder: Option<Remainder>,
    /// What the data say about themselves, stated before anything is
    /// located: bad runs, intervals that look too narrow
    /// ([`super::data_quality`]).
    pub data_quality: DataQuality,
    pub verdict: Verdict,
}

impl Diagnosis {
    /// The laws `diagnose --write-effect` writes: the verdict's located
    /// laws (every step of a found set, in order), else the search's best
    /// (a partial finding is still a starting point to refine); nothing
    /// when none is needed. The study proposes exactly these, by the names
    /// the file gives them ([`super::discovery::write::written_names`]).
    pub fn laws_to_write(&self) -> Vec<Located> {
        let v = &self.verdict;
        if v.kind == VerdictKind::NoneNeeded {
            Vec::new()
        } else if v.located.is_empty() {
            self.discovery
                .as_ref()
                .and_then(|x| x.located.first().cloned())
                .into_iter()
                .collect()
        } else if v.steps.iter().any(|s| s.kind == "located") {
            v.located.clone()
        } else {
            v.located[..1].to_vec()
        }
    }
}

/// A located remainder on top of a catalogue effect.
#[derive(Debug, Clone, Serialize)]
pub struct Remainder {
    pub effect: String,
    pub discovery: Discovery,
}
