//! `swimbot._swimbot`: the Python extension module over the swimbot
//! library. It is thin on purpose: the commands' flags are parsed by the
//! CLI's own parser (so a bad flag gets the CLI's message) and their work
//! is the CLI's (`swimbot::cli::api`), so that every number equals the
//! command's JSON. The Python package (`python/swimbot/__init__.py`) wraps
//! it in keyword arguments, result objects, pandas and HTML.
//!
//! Arrays cross the boundary as bytes of native-endian `f64` (numpy's
//! `tobytes` and `frombuffer`): the limited API (abi3) has no buffer
//! protocol before Python 3.11, and a copy costs nanoseconds against a
//! model evaluation's microsecond.
//!
//! Each call records the files it reads in an [`Inputs`] of its own, so a
//! report written by a notebook names the files its study read, not every
//! file read before in the interpreter. Effects files are loaded the same
//! way, into the call's own catalogue (`swimbot::effects::Catalogue`):
//! nothing one call loads is seen by the next.

use pyo3::create_exception;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyBytes;
use rayon::prelude::*;
use swimbot::cli::{api, Cli, CliError, Command};
use swimbot::data::{self, Case, DataError, ReadOptions};
use swimbot::provenance::Inputs;

create_exception!(
    _swimbot,
    SwimbotError,
    PyValueError,
    "Bad input: the message names the file, the case and the field, as the CLI's does."
);

fn data_err(e: DataError) -> PyErr {
    SwimbotError::new_err(e.to_string())
}

fn cli_err(e: CliError) -> PyErr {
    SwimbotError::new_err(e.to_string())
}

/// A validated dataset: the paper's or a lab's.
#[pyclass(module = "swimbot._swimbot", frozen)]
#[derive(Clone)]
struct Dataset {
    inner: data::Dataset,
    note: Option<String>,
}

#[pymethods]
impl Dataset {
    /// The dataset's name.
    #[getter]
    fn name(&self) -> String {
        self.inner.name.clone()
    }
    /// Where the measurements come from.
    #[getter]
    fn source(&self) -> String {
        self.inner.source.clone()
    }
    /// The case ids, in the file's order.
    #[getter]
    fn ids(&self) -> Vec<String> {
        self.inner.cases.iter().map(|c| c.id.clone()).collect()
    }
    /// What the reader took as what (dialect, recorded columns), if not the format's own.
    #[getter]
    fn note(&self) -> Option<String> {
        self.note.clone()
    }
    fn __len__(&self) -> usize {
        self.inner.cases.len()
    }
    fn __repr__(&self) -> String {
        format!(
            "swimbot.Dataset({:?}, {} cases)",
            self.inner.name,
            self.inner.cases.len()
        )
    }
}

/// The paper's built-in dataset.
#[pyfunction]
fn paper() -> Dataset {
    Dataset {
        inner: data::paper(),
        note: None,
    }
}

/// A dataset file, CSV or TOML (docs/data-format.md).
#[pyfunction]
#[pyo3(signature = (path, decimal_comma = false))]
fn load(py: Python<'_>, path: std::path::PathBuf, decimal_comma: bool) -> PyResult<Dataset> {
    let options = ReadOptions { decimal_comma };
    let loaded = py
        .allow_threads(|| data::read_file(&path, &options, &Inputs::new()))
        .map_err(data_err)?;
    Ok(Dataset {
        inner: loaded.dataset,
        note: loaded.note,
    })
}

/// A dataset from CSV text (what `Dataset.from_pandas` writes); `name`
/// stands for the file in messages.
#[pyfunction]
#[pyo3(signature = (text, name, decimal_comma = false))]
fn from_csv(text: &str, name: &str, decimal_comma: bool) -> PyResult<Dataset> {
    let options = ReadOptions { decimal_comma };
    let dir = std::path::Path::new(".");
    let loaded = data::read_csv_str(text, name, dir, &options, &Inputs::new()).map_err(data_err)?;
    Ok(Dataset {
        inner: loaded.dataset,
        note: loaded.note,
    })
}

/// The CLI's parse of `swimbot COMMAND ARGS...`, its message on error.
fn parse(command: &str, args: Vec<String>) -> PyResult<Command> {
    use clap::Parser;
    let argv = ["swimbot".to_string(), command.to_string()]
        .into_iter()
        .chain(args);
    Cli::try_parse_from(argv)
        .map(|cli| cli.command)
        .map_err(|e| SwimbotError::new_err(e.render().to_string()))
}

fn json<T: serde::Serialize>(value: &T) -> PyResult<String> {
    serde_json::to_string(value).map_err(|e| SwimbotError::new_err(e.to_string()))
}

/// The report's figures of a comparison (parity of U and Omega_b, the
/// strongest residual trends), as SVG text.
fn figures(data: &data::Dataset, cmp: &swimbot::workbench::compare::Comparison) -> Vec<String> {
    use swimbot::report::{parity, residual_plots};
    use swimbot::workbench::compare::Quantity;
    [parity(cmp, Quantity::U), parity(cmp, Quantity::Omega)]
        .into_iter()
        .chain(residual_plots(data, cmp))
        .filter_map(Result::ok)
        .collect()
}

/// `compare --format json` (without the provenance block) and the figures.
#[pyfunction]
fn compare(py: Python<'_>, data: &Dataset, args: Vec<String>) -> PyResult<(String, Vec<String>)> {
    let Command::Compare(a) = parse("compare", args)? else {
        unreachable!("parsed as compare")
    };
    let ds = &data.inner;
    py.allow_threads(|| {
        let c = api::compared(&a, ds, &Inputs::new()).map_err(cli_err)?;
        let cmp = &c.path.last().comparison;
        Ok((json(cmp)?, figures(ds, cmp)))
    })
}

/// `diagnose --format json` (without the provenance block).
#[pyfunction]
fn diagnose(py: Python<'_>, data: &Dataset, args: Vec<String>) -> PyResult<String> {
    let Command::Diagnose(a) = parse("diagnose", args)? else {
        unreachable!("parsed as diagnose")
    };
    let ds = data.inner.clone();
    py.allow_threads(|| {
        let (d, ds) = api::diagnosed(&a, ds, None, &Inputs::new()).map_err(cli_err)?;
        json(&api::diagnosis_json(&d, &ds, a.likelihood.get()).map_err(cli_err)?)
    })
}

/// `fit --format json` (without the provenance block) and the figures of
/// the calibrated model's comparison.
#[pyfunction]
fn fit(py: Python<'_>, data: &Dataset, args: Vec<String>) -> PyResult<(String, Vec<String>)> {
    let Command::Fit(a) = parse("fit", args)? else {
        unreachable!("parsed as fit")
    };
    let ds = &data.inner;
    py.allow_threads(|| {
        let f = api::fitted(&a, ds, &Inputs::new()).map_err(cli_err)?;
        Ok((json(&f.to_json())?, figures(ds, &f.all)))
    })
}

/// `audit --format json` (without the provenance block).
#[pyfunction]
fn audit(py: Python<'_>, data: &Dataset, args: Vec<String>) -> PyResult<String> {
    let Command::Audit(a) = parse("audit", args)? else {
        unreachable!("parsed as audit")
    };
    let ds = &data.inner;
    py.allow_threads(|| json(&api::audited(&a, ds, None, &Inputs::new()).map_err(cli_err)?))
}

fn c_predict(model: &swimbot::model::Model, c: &Case) -> Result<(f64, f64), String> {
    let p = model.predict(c).map_err(|e| e.to_string())?;
    Ok((p.u_mm_s, p.omega_body_hz))
}

fn floats(bytes: Option<&[u8]>, n: usize, name: &str) -> PyResult<Option<Vec<f64>>> {
    let Some(b) = bytes else { return Ok(None) };
    if b.len() != 8 * n {
        return Err(SwimbotError::new_err(format!(
            "{name}: {} bytes for {n} values",
            b.len()
        )));
    }
    Ok(Some(
        b.chunks_exact(8)
            .map(|c| f64::from_ne_bytes(c.try_into().expect("8 bytes")))
            .collect(),
    ))
}

/// The model of a sweep: the study's calibrated model (every step, its
/// located laws included, which only the study knows) or the flags' one.
fn sweep_model(args: Vec<String>, study: Option<&Study>) -> PyResult<swimbot::model::Model> {
    let Command::Compare(a) = parse("compare", args.clone())? else {
        unreachable!("parsed as compare")
    };
    match study {
        Some(_) if !args.is_empty() => Err(SwimbotError::new_err(
            "sweep: study and preset/effects: give one or the other (the study's model is its preset with its steps)",
        )),
        Some(s) => s.with(|s| s.model()).map_err(study_err),
        None => a.model.model(&Inputs::new()).map_err(cli_err),
    }
}

/// The model's U (mm/s) and Omega_b (Hz) at `n` geometries: each column
/// (native f64 bytes, `n` values) replaces the template case's field, an
/// absent one keeps it. With `study`, the study's model on its data's
/// cases (unless `template` names other data). Parallel, the GIL
/// released; the first bad geometry is an error naming its index and field.
#[pyfunction]
#[pyo3(signature = (n, args, template = None, case = None, wavelength_mm = None, amplitude_mm = None, tail_length_mm = None, frequency_hz = None, study = None))]
#[allow(clippy::too_many_arguments)]
fn sweep<'py>(
    py: Python<'py>,
    n: usize,
    args: Vec<String>,
    template: Option<&Dataset>,
    case: Option<String>,
    wavelength_mm: Option<&[u8]>,
    amplitude_mm: Option<&[u8]>,
    tail_length_mm: Option<&[u8]>,
    frequency_hz: Option<&[u8]>,
    study: Option<PyRef<'py, Study>>,
) -> PyResult<(Bound<'py, PyBytes>, Bound<'py, PyBytes>)> {
    let model = sweep_model(args, study.as_deref())?;
    let base = match (template, &study) {
        (Some(d), _) => d.inner.clone(),
        (None, Some(s)) => s.with(|s| s.dataset().clone()),
        (None, None) => data::paper(),
    };
    let mut t: Case = match &case {
        Some(id) => base
            .cases
            .iter()
            .find(|c| &c.id == id)
            .cloned()
            .ok_or_else(|| {
                let ids: Vec<&str> = base.cases.iter().map(|c| c.id.as_str()).collect();
                SwimbotError::new_err(format!(
                    "case: no case `{id}` in the data; cases: {}",
                    ids.join(", ")
                ))
            })?,
        None => base.cases[0].clone(),
    };
    t.u_mm_s = None;
    t.omega_body_hz = None;
    // What only the data's statistics read: not cloned per geometry.
    t.inputs = Default::default();
    t.recorded = Default::default();
    let cols = [
        ("wavelength_mm", floats(wavelength_mm, n, "wavelength_mm")?),
        ("amplitude_mm", floats(amplitude_mm, n, "amplitude_mm")?),
        (
            "tail_length_mm",
            floats(tail_length_mm, n, "tail_length_mm")?,
        ),
        ("frequency_hz", floats(frequency_hz, n, "frequency_hz")?),
    ];
    // The template is checked whole once; per geometry only what a column
    // changes: its range, and the relations it enters (turns, the robot's
    // length in the channel), with `check_case`'s own message when one
    // fails. Checking every field of every geometry, and cloning the case
    // for each, had cost more than the prediction.
    data::limits::check_case(&t)
        .map_err(|(f, m)| SwimbotError::new_err(format!("template case: {f}: {m}")))?;
    let given: Vec<(&str, &data::limits::Limit, Vec<f64>)> = cols
        .into_iter()
        .filter_map(|(name, col)| {
            let limit = data::limits::limit_of(name).expect("a dataset field");
            col.map(|v| (name, limit, v))
        })
        .collect();
    let set = |c: &mut Case, i: usize| {
        for (name, _, v) in &given {
            let slot = match *name {
                "wavelength_mm" => &mut c.wavelength_mm,
                "amplitude_mm" => &mut c.amplitude_mm,
                "tail_length_mm" => &mut c.tail_length_mm,
                _ => &mut c.frequency_hz,
            };
            *slot = v[i];
        }
    };
    let in_limits = |c: &Case, i: usize| {
        let ranges = given
            .iter()
            .all(|(_, l, v)| v[i].is_finite() && v[i] >= l.min && v[i] <= l.max);
        ranges
            && c.tail_length_mm / c.wavelength_mm <= data::limits::MAX_TURNS
            && c.body_length_mm + c.coupler_length_mm + c.tail_length_mm <= c.channel_length_mm
    };
    let out: Result<Vec<(f64, f64)>, String> = py.allow_threads(|| {
        (0..n)
            .into_par_iter()
            .map_init(
                || t.clone(),
                |c, i| {
                    set(c, i);
                    if !in_limits(c, i) {
                        data::limits::check_case(c)
                            .map_err(|(f, m)| format!("geometry {i}: {f}: {m}"))?;
                    }
                    let p = c_predict(&model, c).map_err(|e| format!("geometry {i}: {e}"))?;
                    Ok(p)
                },
            )
            .collect()
    });
    let out = out.map_err(SwimbotError::new_err)?;
    let bytes = |f: fn(&(f64, f64)) -> f64| -> Vec<u8> {
        out.iter().flat_map(|p| f(p).to_ne_bytes()).collect()
    };
    Ok((
        PyBytes::new(py, &bytes(|p| p.0)),
        PyBytes::new(py, &bytes(|p| p.1)),
    ))
}

fn study_err(e: swimbot::study::StudyError) -> PyErr {
    SwimbotError::new_err(e.to_string())
}

/// A study (`swimbot-study.toml`): the user's model built step by step on
/// one dataset, over the library's `swimbot::study::Study`. Every method
/// that changes it writes the file, as `swimbot add` and `undo` do.
#[pyclass(module = "swimbot._swimbot")]
struct Study {
    inner: std::sync::Mutex<swimbot::study::Study>,
}

impl Study {
    fn with<T>(&self, f: impl FnOnce(&mut swimbot::study::Study) -> T) -> T {
        // A panic in an earlier call poisons nothing the study depends on:
        // its state is the file, re-read by `open`.
        let mut g = self.inner.lock().unwrap_or_else(|p| p.into_inner());
        f(&mut g)
    }
}

fn likelihood_of(name: &str) -> PyResult<swimbot::workbench::robust::Likelihood> {
    use swimbot::workbench::robust::Likelihood;
    match name {
        "gaussian" => Ok(Likelihood::Gaussian),
        "student-t" => Ok(Likelihood::StudentT),
        other => Err(SwimbotError::new_err(format!(
            "likelihood: `{other}` is not one: gaussian or student-t"
        ))),
    }
}

/// `swimbot init`: a new study at `path` on the dataset at `data`.
#[pyfunction]
#[pyo3(signature = (path, data, preset = "base".to_string(), likelihood = "gaussian".to_string(), force = false, diagnose = true))]
fn study_init(
    py: Python<'_>,
    path: std::path::PathBuf,
    data: std::path::PathBuf,
    preset: String,
    likelihood: String,
    force: bool,
    diagnose: bool,
) -> PyResult<Study> {
    let o = swimbot::study::InitOptions {
        preset,
        likelihood: likelihood_of(&likelihood)?,
        force,
        diagnose,
    };
    let s = py
        .allow_threads(|| swimbot::study::Study::init(&path, &data, &o))
        .map_err(study_err)?;
    Ok(Study {
        inner: std::sync::Mutex::new(s),
    })
}

/// Open the study at `path` (its dataset checked against the pinned SHA-256).
#[pyfunction]
fn study_open(py: Python<'_>, path: std::path::PathBuf) -> PyResult<Study> {
    let s = py
        .allow_threads(|| swimbot::study::Study::open(&path))
        .map_err(study_err)?;
    Ok(Study {
        inner: std::sync::Mutex::new(s),
    })
}

#[pymethods]
impl Study {
    /// The study file's path.
    #[getter]
    fn path(&self) -> std::path::PathBuf {
        self.with(|s| s.path().to_path_buf())
    }
    /// The study's dataset.
    #[getter]
    fn dataset(&self) -> Dataset {
        Dataset {
            inner: self.with(|s| s.dataset().clone()),
            note: None,
        }
    }
    /// The whole study as `swimbot steps --format json` prints it.
    fn to_json(&self) -> PyResult<String> {
        self.with(|s| json(s.file()))
    }
    /// `swimbot add EFFECT | FILE[#NAME]`: the new step as JSON.
    #[pyo3(signature = (effect, refit_all = false, force = false, diagnose = true))]
    fn add(
        &self,
        py: Python<'_>,
        effect: &str,
        refit_all: bool,
        force: bool,
        diagnose: bool,
    ) -> PyResult<String> {
        let def = api::definition(effect, &Inputs::new()).map_err(cli_err)?;
        let o = swimbot::study::AddOptions {
            refit_all,
            force,
            diagnose,
        };
        py.allow_threads(|| self.with(|s| json(s.add(def, &o).map_err(study_err)?)))
    }
    /// `swimbot undo`: the removed step as JSON.
    fn undo(&self) -> PyResult<String> {
        self.with(|s| json(&s.undo().map_err(study_err)?))
    }
    /// `swimbot steps --data`: the study's models on other data, every
    /// parameter held, as JSON.
    fn apply_to(&self, py: Python<'_>, data: &Dataset) -> PyResult<String> {
        let d = &data.inner;
        py.allow_threads(|| self.with(|s| json(&s.apply_to(d).map_err(study_err)?)))
    }
    /// `swimbot report` of the study: the page's bundle written to `dir`
    /// (refused where `report` refuses it); the page's path. Its inputs
    /// are the files the study read, whatever else this process has read;
    /// its command line, the one `swimbot report` would have been given.
    /// The folder is marked as `report`'s, as the command marks it.
    fn report(&self, py: Python<'_>, dir: std::path::PathBuf) -> PyResult<std::path::PathBuf> {
        let inputs = self.with(|s| {
            let command = [
                "swimbot",
                "--study",
                &s.path().display().to_string(),
                "report",
            ]
            .into_iter()
            .map(str::to_string)
            .chain(["-o".to_string(), dir.display().to_string()])
            .collect();
            s.inputs().clone().with_command(command)
        });
        api::check_output_dir(&dir, "report", &inputs).map_err(cli_err)?;
        let written = swimbot::report::check_bundle_dir(&dir, "report")
            .map_err(|e| SwimbotError::new_err(e.to_string()))
            .and_then(|()| {
                let guard = |p: &std::path::Path| api::not_an_input(p, &inputs);
                py.allow_threads(|| {
                    self.with(|s| {
                        swimbot::report::write_study(&dir, s, &guard, &inputs).map_err(|e| {
                            SwimbotError::new_err(format!(
                                "writing the report to {}: {e}",
                                dir.display()
                            ))
                        })
                    })
                })
            });
        if written.is_ok() {
            api::mark_claimed_dirs(&inputs);
        }
        api::settle_output_dir(&dir, written.is_ok());
        written
    }
    fn __repr__(&self) -> String {
        self.with(|s| {
            format!(
                "swimbot.Study({:?}, {} step(s))",
                s.path().display().to_string(),
                s.steps().len()
            )
        })
    }
}

#[pymodule]
fn _swimbot(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("SwimbotError", m.py().get_type::<SwimbotError>())?;
    m.add_class::<Dataset>()?;
    m.add_function(wrap_pyfunction!(paper, m)?)?;
    m.add_function(wrap_pyfunction!(load, m)?)?;
    m.add_function(wrap_pyfunction!(from_csv, m)?)?;
    m.add_function(wrap_pyfunction!(compare, m)?)?;
    m.add_function(wrap_pyfunction!(diagnose, m)?)?;
    m.add_function(wrap_pyfunction!(fit, m)?)?;
    m.add_function(wrap_pyfunction!(audit, m)?)?;
    m.add_function(wrap_pyfunction!(sweep, m)?)?;
    m.add_class::<Study>()?;
    m.add_function(wrap_pyfunction!(study_init, m)?)?;
    m.add_function(wrap_pyfunction!(study_open, m)?)?;
    Ok(())
}
