//! `swimbot sweep`: predictions over a grid of tail geometries, frequencies
//! and channel diameters, computed in parallel and written as CSV.

use super::model_args::ModelArgs;
use super::CliError;
use crate::data::Case;
use crate::model::Model;
use crate::provenance::Inputs;
use clap::Args;
use rayon::prelude::*;
use std::io::Write;
use std::path::PathBuf;

#[derive(Args, Debug)]
pub struct SweepArgs {
    // Hyphen values are accepted so that `-1:20:3` reaches the range
    // parser (and its message) instead of being read as a flag.
    /// Helix wavelength lambda in mm: start:stop:count (count values, ends included) or one value.
    #[arg(long, value_name = "A:B:N", allow_hyphen_values = true)]
    pub wavelength_mm: String,
    /// Helix amplitude B (radius of the helix's centre-line) in mm: start:stop:count or one value.
    #[arg(long, value_name = "A:B:N", allow_hyphen_values = true)]
    pub amplitude_mm: String,
    /// Axial tail length L_t in mm: start:stop:count or one value.
    #[arg(long, value_name = "A:B:N", allow_hyphen_values = true)]
    pub tail_length_mm: String,
    /// Tail rotation rate f in Hz: start:stop:count or one value.
    #[arg(
        long,
        value_name = "A:B:N",
        default_value = "1.0",
        allow_hyphen_values = true
    )]
    pub frequency_hz: String,
    /// Channel inner diameter in mm: start:stop:count or one value [default: the
    /// setup's, 35 mm for the paper].
    #[arg(long, value_name = "A:B:N", allow_hyphen_values = true)]
    pub channel_diameter_mm: Option<String>,
    /// Dataset (TOML or CSV) whose setup the sweep uses: body, coupler, oil, wire and
    /// channel (diameter, length, ends, orientation) [default: the study's data inside a
    /// study, else the paper's first case].
    #[arg(long, value_name = "FILE")]
    pub data: Option<PathBuf>,
    /// With --data or inside a study: the case whose setup is used [default: the first, if
    /// every case has the same setup].
    #[arg(long, value_name = "ID")]
    pub case: Option<String>,
    /// A study's data with its run sheets joined (never a flag): the
    /// cases `--case` picks from when the sweep works in a study.
    #[arg(skip)]
    pub joined: Option<crate::data::Dataset>,
    #[command(flatten)]
    pub model: ModelArgs,
    /// Output CSV file [default: stdout].
    #[arg(short, long, value_name = "FILE.csv")]
    pub output: Option<PathBuf>,
    /// Refuse the sweep when its estimated run time (timed on a sample of
    /// grid points before the work) is longer [default: no limit; a sweep
    /// estimated over 10 s is announced on stderr].
    #[arg(long, value_name = "SECONDS")]
    pub max_seconds: Option<f64>,
}

/// Grid points of one sweep: the rows are kept in memory (~100 bytes each
/// with their CSV line), so this bounds memory near 1 GB and the run near a
/// minute per million points on two cores.
pub const MAX_GRID_POINTS: usize = 10_000_000;

/// A parsed `start:stop:count` range.
#[derive(Debug, Clone, PartialEq)]
pub struct Range {
    pub values: Vec<f64>,
}

pub fn parse_range(flag: &str, text: &str) -> Result<Range, CliError> {
    let bad = |why: &str| {
        CliError::input(format!(
            "--{flag} `{text}`: {why} (expected start:stop:count or one value)"
        ))
    };
    let parts: Vec<&str> = text.split(':').collect();
    let num = |s: &str| -> Result<f64, CliError> {
        s.trim()
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite() && *v > 0.0)
            .ok_or_else(|| bad(&format!("`{s}` is not a positive number")))
    };
    match parts.as_slice() {
        [v] => Ok(Range {
            values: vec![num(v)?],
        }),
        [a, b, n] => {
            let (a, b) = (num(a)?, num(b)?);
            let n: usize = n
                .trim()
                .parse()
                .ok()
                .filter(|n| (1..=MAX_GRID_POINTS).contains(n))
                .ok_or_else(|| {
                    bad(&format!(
                        "count must be a whole number from 1 to {MAX_GRID_POINTS}"
                    ))
                })?;
            if n == 1 && a != b {
                return Err(bad("a count of 1 needs start = stop"));
            }
            let values = (0..n)
                .map(|i| {
                    if n == 1 {
                        a
                    } else {
                        a + (b - a) * i as f64 / (n - 1) as f64
                    }
                })
                .collect();
            Ok(Range { values })
        }
        _ => Err(bad("wrong number of fields")),
    }
}

struct Grid {
    wavelength: Range,
    amplitude: Range,
    length: Range,
    frequency: Range,
    channel: Range,
}

impl Grid {
    /// Number of points (saturating: the product is checked before use).
    fn len(&self) -> usize {
        [
            &self.wavelength,
            &self.amplitude,
            &self.length,
            &self.frequency,
            &self.channel,
        ]
        .iter()
        .fold(1usize, |n, r| n.saturating_mul(r.values.len()))
    }

    /// The `i`-th grid point (row-major, channel fastest): wavelength,
    /// amplitude, tail length, frequency and channel diameter.
    fn point(&self, mut i: usize) -> [f64; 5] {
        let mut pick = |r: &Range| {
            let n = r.values.len();
            let v = r.values[i % n];
            i /= n;
            v
        };
        let channel = pick(&self.channel);
        let frequency = pick(&self.frequency);
        let length = pick(&self.length);
        let amplitude = pick(&self.amplitude);
        let wavelength = pick(&self.wavelength);
        [wavelength, amplitude, length, frequency, channel]
    }

    /// Sets `case` to the `i`-th grid point; the rest stays the template's.
    fn put(&self, case: &mut Case, i: usize) {
        let [wavelength, amplitude, length, frequency, channel] = self.point(i);
        case.wavelength_mm = wavelength;
        case.amplitude_mm = amplitude;
        case.tail_length_mm = length;
        case.frequency_hz = frequency;
        case.channel_diameter_mm = channel;
    }

    /// The `i`-th grid point as a case.
    fn case(&self, template: &Case, i: usize) -> Case {
        let mut case = template.clone();
        self.put(&mut case, i);
        case
    }
}

/// Predictions of one grid point.
struct Row {
    u_mm_s: f64,
    /// Body counter-rotation Omega_b (Hz), positive against the tail.
    omega_hz: f64,
    u_ratio: f64,
    omega_ratio: f64,
}

/// Inside a study (and without `--data` or model flags) the sweep is of
/// the study's calibrated model, every step's law included, on its data's
/// setup, as `compare` inside the study is: the steps' user effects are
/// known only to the study, so naming them with `--effect` cannot work.
pub fn in_study(
    a: &mut SweepArgs,
    study: &Option<PathBuf>,
    inputs: &Inputs,
) -> Result<(), CliError> {
    let mut data = super::model_args::DataArgs {
        data: a.data.take(),
        decimal_comma: false,
        joined: None,
    };
    super::study::fill_from_study(study, &mut data, &mut a.model, inputs)?;
    a.data = data.data;
    a.joined = data.joined;
    Ok(())
}

pub fn run(a: SweepArgs, inputs: &Inputs) -> Result<(), CliError> {
    let mut template = super::sweep_setup::template(
        a.data.as_ref(),
        a.joined.as_ref(),
        a.case.as_deref(),
        inputs,
    )?;
    let channel = match &a.channel_diameter_mm {
        Some(text) => text.clone(),
        None => template.channel_diameter_mm.to_string(),
    };
    let grid = Grid {
        wavelength: parse_range("wavelength-mm", &a.wavelength_mm)?,
        amplitude: parse_range("amplitude-mm", &a.amplitude_mm)?,
        length: parse_range("tail-length-mm", &a.tail_length_mm)?,
        frequency: parse_range("frequency-hz", &a.frequency_hz)?,
        channel: parse_range("channel-diameter-mm", &channel)?,
    };
    let model = a.model.model(inputs)?;
    template.id = "sweep".into();
    template.u_mm_s = None;
    template.omega_body_hz = None;
    check_grid(&grid, &template)?;
    let n = grid.len();
    if n > MAX_GRID_POINTS {
        return Err(CliError::input(format!(
            "the sweep has {n} grid points; at most {MAX_GRID_POINTS} are allowed (split it into several runs)"
        )));
    }
    if let Some(p) = &a.output {
        super::output::check_output_file(p, inputs)?;
    }
    let budget = super::budget::parse_budget(a.max_seconds)?;
    // 32 points spread over the grid: the cost of one varies with the geometry.
    let sample = 32.min(n);
    let per_point = super::budget::seconds_per_call(sample, |j| {
        let _ = predict_row(&model, &grid.case(&template, j * n / sample));
    });
    let estimate = per_point * n as f64 / rayon::current_num_threads() as f64;
    super::budget::check(&format!("the sweep of {n} grid points"), estimate, budget)?;
    let bar = crate::progress::bar(n as u64, "geometries", "sweep");
    // One case per worker, moved from point to point: a case's clone (its
    // strings and optional fields) cost more than a tenth of a prediction.
    let rows: Result<Vec<Row>, CliError> = (0..n)
        .into_par_iter()
        .map_init(
            || template.clone(),
            |case, i| {
                grid.put(case, i);
                if i % 4096 == 0 {
                    bar.inc(4096.min(n - i) as u64);
                }
                predict_row(&model, case)
            },
        )
        .collect();
    // Writing millions of rows takes longer than computing them.
    bar.set_message("sweep: writing");
    bar.set_position(0);
    let written = write_csv(&grid, &rows?, a.output.as_ref(), &bar, inputs);
    bar.finish_and_clear();
    written
}

fn predict_row(model: &Model, case: &Case) -> Result<Row, CliError> {
    let p = model.predict(case)?;
    Ok(Row {
        u_mm_s: p.u_mm_s,
        omega_hz: p.omega_body_hz,
        u_ratio: p.u_over_u_wave,
        omega_ratio: p.omega_ratio,
    })
}

/// Reject grids with points the model cannot evaluate, before the work.
fn check_grid(g: &Grid, t: &Case) -> Result<(), CliError> {
    let max = |r: &Range| r.values.iter().copied().fold(f64::MIN, f64::max);
    let min = |r: &Range| r.values.iter().copied().fold(f64::MAX, f64::min);
    for (flag, field, r) in [
        ("wavelength-mm", "wavelength_mm", &g.wavelength),
        ("amplitude-mm", "amplitude_mm", &g.amplitude),
        ("tail-length-mm", "tail_length_mm", &g.length),
        ("frequency-hz", "frequency_hz", &g.frequency),
        ("channel-diameter-mm", "channel_diameter_mm", &g.channel),
    ] {
        for v in [min(r), max(r)] {
            crate::data::limits::check_value(field, v)
                .map_err(|e| CliError::input(format!("--{flag}: {e}")))?;
        }
    }
    // The corner of the grid with the most turns and the longest robot.
    let mut corner = t.clone();
    corner.wavelength_mm = min(&g.wavelength);
    corner.tail_length_mm = max(&g.length);
    corner.channel_diameter_mm = min(&g.channel);
    crate::data::limits::check_case(&corner)
        .map_err(|(f, e)| CliError::input(format!("sweep grid: {f}: {e}")))?;
    if min(&g.wavelength) <= 2.0 * t.wire_diameter_mm {
        return Err(CliError::input(format!(
            "--wavelength-mm: {} mm is too short for the {} mm wire (the RFT logarithms need lambda > 2 D_t)",
            min(&g.wavelength),
            t.wire_diameter_mm
        )));
    }
    if max(&g.amplitude) + 0.5 * t.wire_diameter_mm >= 0.5 * min(&g.channel) {
        return Err(CliError::input(format!(
            "--amplitude-mm: a {} mm helix does not fit in a {} mm channel",
            max(&g.amplitude),
            min(&g.channel)
        )));
    }
    if t.body_diameter_mm >= min(&g.channel) {
        return Err(CliError::input(format!(
            "--channel-diameter-mm: {} mm is not wider than the {} mm body",
            min(&g.channel),
            t.body_diameter_mm
        )));
    }
    Ok(())
}

/// Rows formatted by one task.
const FORMAT_CHUNK_ROWS: usize = 8192;
/// Rows formatted before they are written: enough tasks to keep every
/// core busy, few enough that the text (about 18 MB) stays small; the
/// same buffers serve every batch.
const WRITE_BATCH_ROWS: usize = 16 * FORMAT_CHUNK_ROWS;

/// The grid's values as CSV cells, each range's formatted once: a sweep
/// repeats every one of them on many rows.
struct GridCells {
    wavelength: Vec<String>,
    amplitude: Vec<String>,
    length: Vec<String>,
    frequency: Vec<String>,
    channel: Vec<String>,
}

impl GridCells {
    fn new(g: &Grid) -> Self {
        let cells = |r: &Range| {
            r.values
                .iter()
                .map(|&v| crate::format::csv_f64(v))
                .collect()
        };
        GridCells {
            wavelength: cells(&g.wavelength),
            amplitude: cells(&g.amplitude),
            length: cells(&g.length),
            frequency: cells(&g.frequency),
            channel: cells(&g.channel),
        }
    }

    /// A CSV line's length, as reserved: the longest cell of each range,
    /// four predictions of 24 characters (17 digits, sign, point and a
    /// few zeros; a magnitude far from 1, written out in full, is longer
    /// and grows the buffer), the commas and the newline. Reserved at once,
    /// a chunk's text is never copied to a larger buffer.
    fn line_bound(&self) -> usize {
        let longest = |cells: &[String]| cells.iter().map(String::len).max().unwrap_or(0);
        longest(&self.wavelength)
            + longest(&self.amplitude)
            + longest(&self.length)
            + longest(&self.frequency)
            + longest(&self.channel)
            + 4 * 24
            + 9
    }

    /// The cells of the `i`-th grid point in [`Grid::point`]'s order.
    fn point(&self, mut i: usize) -> [&str; 5] {
        fn pick<'a>(cells: &'a [String], i: &mut usize) -> &'a str {
            let n = cells.len();
            let c = cells[*i % n].as_str();
            *i /= n;
            c
        }
        let channel = pick(&self.channel, &mut i);
        let frequency = pick(&self.frequency, &mut i);
        let length = pick(&self.length, &mut i);
        let amplitude = pick(&self.amplitude, &mut i);
        let wavelength = pick(&self.wavelength, &mut i);
        [wavelength, amplitude, length, frequency, channel]
    }
}

/// Appends the CSV lines of `rows`, the first of which is grid point
/// `first`, to `out`, in the one CSV style (crate::format): shortest
/// round-trip decimals, as `{}` writes them.
fn csv_lines(cells: &GridCells, first: usize, rows: &[Row], out: &mut Vec<u8>) {
    out.reserve(rows.len() * cells.line_bound());
    for (j, r) in rows.iter().enumerate() {
        for c in cells.point(first + j) {
            out.extend_from_slice(c.as_bytes());
            out.push(b',');
        }
        crate::format::push_csv_f64(out, r.u_mm_s);
        out.push(b',');
        crate::format::push_csv_f64(out, r.omega_hz);
        out.push(b',');
        crate::format::push_csv_f64(out, r.u_ratio);
        out.push(b',');
        crate::format::push_csv_f64(out, r.omega_ratio);
        out.push(b'\n');
    }
}

fn write_csv(
    g: &Grid,
    rows: &[Row],
    out: Option<&PathBuf>,
    bar: &indicatif::ProgressBar,
    inputs: &Inputs,
) -> Result<(), CliError> {
    // A file is written to a temporary sibling and renamed at the end, so
    // a failure never leaves half a CSV under the requested name.
    let mut pending = match out {
        Some(p) => Some(super::output::AtomicFile::create(p, inputs)?),
        None => None,
    };
    let sink: Box<dyn Write + '_> = match pending.as_mut() {
        Some(f) => Box::new(f.writer()),
        None => Box::new(std::io::stdout().lock()),
    };
    let mut w = std::io::BufWriter::with_capacity(1 << 20, sink);
    // A write that fails (a full disk, a closed device) is the user's to
    // fix: exit 2; a reader of stdout that stopped early ends the run quietly.
    let to = out.map_or("standard output".to_string(), |p| p.display().to_string());
    let fail = |e: std::io::Error| match out {
        None => super::stdout::stdout_error(e, "the sweep CSV"),
        Some(_) => CliError::input(format!("cannot write the sweep CSV to {to}: {e}")),
    };
    let provenance = crate::provenance::Provenance::capture(inputs).comment_block();
    w.write_all(provenance.as_bytes()).map_err(fail)?;
    writeln!(
        w,
        "wavelength_mm,amplitude_mm,tail_length_mm,frequency_hz,channel_diameter_mm,u_mm_s,omega_body_counter_hz,u_over_u_wave,omega_body_counter_over_f"
    )
    .map_err(fail)?;
    // Shortest round-trip decimals cost more than the model itself, and one
    // thread writing them was most of a sweep's wall time: each batch of
    // rows is formatted in parallel, chunk by chunk, and written in order.
    // A batch bounds the formatted text held at once (about 50 MB).
    // The chunks' buffers serve every batch: fresh ones cost a page fault
    // per 4 KiB of text, each batch again.
    let cells = GridCells::new(g);
    let mut text: Vec<Vec<u8>> = Vec::new();
    for (b, batch) in rows.chunks(WRITE_BATCH_ROWS).enumerate() {
        let start = b * WRITE_BATCH_ROWS;
        let chunks = batch.len().div_ceil(FORMAT_CHUNK_ROWS);
        if text.len() < chunks {
            text.resize_with(chunks, Vec::new);
        }
        text[..chunks]
            .par_iter_mut()
            .zip(batch.par_chunks(FORMAT_CHUNK_ROWS))
            .enumerate()
            .for_each(|(k, (out, chunk))| {
                out.clear();
                csv_lines(&cells, start + k * FORMAT_CHUNK_ROWS, chunk, out);
            });
        for t in &text[..chunks] {
            w.write_all(t).map_err(fail)?;
        }
        bar.inc(batch.len() as u64);
    }
    w.flush().map_err(fail)?;
    drop(w);
    match pending {
        Some(f) => f.commit(),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_parse_and_reject_with_the_flag_name() {
        assert_eq!(parse_range("x", "2").unwrap().values, vec![2.0]);
        assert_eq!(
            parse_range("x", "1:3:3").unwrap().values,
            vec![1.0, 2.0, 3.0]
        );
        for bad in [
            "1:2",
            "a:2:3",
            "1:2:0",
            "-1:2:2",
            "1:2:1",
            "1:2:x",
            "1:2:1000000000",
        ] {
            let e = parse_range("wavelength-mm", bad).unwrap_err().to_string();
            assert!(e.contains("--wavelength-mm"), "{bad}: {e}");
        }
    }
}
