//! Scatter, curve and parity charts: the [`Chart`] builder lays out one
//! panel (axes, data, point labels, a legend that covers no data, notes)
//! and renders it alone or stacked with others sharing a width.

use super::frame::{left_px, top_px, Frame, BOTTOM_PX, RIGHT_PX};
use super::geom::{Rect, Shape};
use super::legend::{self, Entry, Glyph};
use super::series::Series;
use super::svg::{Anchor, Stroke, Svg};
use super::svg_text::width;
use super::ticks::Axis;
use super::PlotResult;
use plotters::style::RGBColor;

const MARKER_R: f64 = 4.0;
const CAP_PX: f64 = 3.0;
const LABEL_FONT_PX: f64 = 10.0;
const NOTE_FONT_PX: f64 = 11.0;
const NOTE_ROW_PX: f64 = 15.0;
const REFERENCE: RGBColor = RGBColor(110, 110, 110);

/// A horizontal reference line (an observed value, zero).
#[derive(Debug, Clone)]
struct Reference {
    y: f64,
    label: String,
    color: RGBColor,
}

/// One chart panel, configured by builder methods, drawn by [`Chart::render`].
#[derive(Debug, Clone)]
pub struct Chart {
    title: String,
    x_desc: String,
    y_desc: String,
    size: (f64, f64),
    log_x: bool,
    log_y: bool,
    diagonal: bool,
    include_zero_y: bool,
    x_range: Option<(f64, f64)>,
    notes: Vec<String>,
    references: Vec<Reference>,
    entries: Vec<Entry>,
}

impl Chart {
    /// A 560 x 380 linear chart; titles may use code notation (`Omega_b`).
    pub fn new(title: &str, x_desc: &str, y_desc: &str) -> Self {
        Self {
            title: title.into(),
            x_desc: x_desc.into(),
            y_desc: y_desc.into(),
            size: (560.0, 380.0),
            log_x: false,
            log_y: false,
            diagonal: false,
            include_zero_y: false,
            x_range: None,
            notes: Vec::new(),
            references: Vec::new(),
            entries: Vec::new(),
        }
    }

    /// Size of the panel before any outside legend or notes are added.
    pub fn size(mut self, w: u32, h: u32) -> Self {
        self.size = (w as f64, h as f64);
        self
    }

    pub fn log_x(mut self) -> Self {
        self.log_x = true;
        self
    }

    pub fn log_y(mut self) -> Self {
        self.log_y = true;
        self
    }

    /// Parity: the same range on both axes and the line y = x.
    pub fn diagonal(mut self) -> Self {
        self.diagonal = true;
        self
    }

    pub fn include_zero_y(mut self) -> Self {
        self.include_zero_y = true;
        self
    }

    /// Fixes the x range (panels sharing a time axis).
    pub fn x_range(mut self, lo: f64, hi: f64) -> Self {
        self.x_range = Some((lo, hi));
        self
    }

    /// A line of text under the figure.
    pub fn note(mut self, text: impl Into<String>) -> Self {
        self.notes.push(text.into());
        self
    }

    /// A dashed horizontal reference line at `y` (in the legend when labelled).
    pub fn hline(mut self, y: f64, label: impl Into<String>, color: RGBColor) -> Self {
        self.references.push(Reference {
            y,
            label: label.into(),
            color,
        });
        self
    }

    /// A zero line (residual plots).
    pub fn zero_line(self) -> Self {
        self.hline(0.0, "", REFERENCE)
    }

    /// A legend entry not tied to one series (what bars or lines mean).
    pub fn legend_entry(mut self, glyph: Glyph, color: RGBColor, label: impl Into<String>) -> Self {
        self.entries.push(Entry {
            glyph,
            color,
            label: label.into(),
        });
        self
    }

    /// The chart as a standalone SVG document.
    pub fn render(&self, series: &[Series]) -> PlotResult {
        stack("", &[(self.clone(), series.to_vec())])
    }
}

/// Panels stacked top to bottom under one title, each laid out on its own.
pub fn stack(title: &str, panels: &[(Chart, Vec<Series>)]) -> PlotResult {
    if panels.is_empty() {
        return Err("no panels to draw".into());
    }
    let mut svg = Svg::default();
    let mut y = if title.is_empty() { 0.0 } else { 28.0 };
    let mut w: f64 = 0.0;
    // Panels share one left edge so stacked time axes line up.
    let left = panels
        .iter()
        .map(|(c, s)| y_ticks_and_left(c, s).1)
        .fold(0.0, f64::max);
    for (chart, series) in panels {
        let (pw, ph) = draw_panel(&mut svg, chart, series, (0.0, y), left)?;
        w = w.max(pw);
        y += ph;
    }
    if !title.is_empty() {
        svg.group("frame");
        svg.text((0.5 * w, 20.0), title, 16.0, Anchor::Middle, true, false);
        svg.end_group();
    }
    Ok(svg.finish(w.ceil(), y.ceil()))
}

/// Pixel mapping of one panel.
struct Map {
    plot: Rect,
    x: Axis,
    y: Axis,
}

impl Map {
    fn px(&self, x: f64, y: f64) -> Option<(f64, f64)> {
        Some((
            self.plot.x0 + self.x.frac(x)? * self.plot.width(),
            self.plot.y1 - self.y.frac(y)? * self.plot.height(),
        ))
    }
}

fn axes(c: &Chart, series: &[Series]) -> (Axis, Axis) {
    let mut xs = Vec::new();
    let mut ys = Vec::new();
    for s in series {
        for (i, p) in s.points.iter().enumerate() {
            let (ey, ex) = if s.line {
                (0.0, 0.0)
            } else {
                (p.2, s.x_err.get(i).copied().unwrap_or(0.0))
            };
            xs.extend([p.0 - ex, p.0 + ex]);
            ys.extend([p.1 - ey, p.1 + ey]);
        }
    }
    ys.extend(c.references.iter().map(|r| r.y));
    if c.diagonal {
        let all: Vec<f64> = xs.iter().chain(&ys).copied().collect();
        let log = c.log_x || c.log_y;
        let a = Axis::fit(all.into_iter(), log, !log);
        return (a, a);
    }
    let x = match c.x_range {
        Some((lo, hi)) => Axis {
            lo,
            hi,
            log: c.log_x,
        },
        None => Axis::fit(xs.into_iter(), c.log_x, false),
    };
    (x, Axis::fit(ys.into_iter(), c.log_y, c.include_zero_y))
}

/// Pixels per x tick and per y tick a reader needs to take them in.
const X_TICK_PX: f64 = 80.0;
const Y_TICK_PX: f64 = 35.0;

/// The y ticks of a panel and the width left of its plot they need.
fn y_ticks_and_left(c: &Chart, series: &[Series]) -> (Vec<(f64, String)>, f64) {
    let (_, y) = axes(c, series);
    let ticks = y.ticks((c.size.1 - top_px(&c.title) - BOTTOM_PX) / Y_TICK_PX);
    let left = left_px(&ticks.iter().map(|t| t.1.clone()).collect::<Vec<_>>());
    (ticks, left)
}

/// A point's label: text, anchor point, and its box.
struct Label {
    text: String,
    at: (f64, f64),
    anchor: Anchor,
    bbox: Rect,
}

fn place_label(text: &str, p: (f64, f64), plot: Rect, avoid: &[Shape], placed: &[Label]) -> Label {
    let w = width(text, LABEL_FONT_PX);
    let h = LABEL_FONT_PX;
    let d = MARKER_R + 3.0;
    // (x of the text's left edge, baseline y, anchor)
    let candidates = [
        (p.0 + d, p.1 + 3.5, Anchor::Start),
        (p.0 + d - 2.0, p.1 - d, Anchor::Start),
        (p.0 + d - 2.0, p.1 + d + h - 2.0, Anchor::Start),
        (p.0 - d - w, p.1 + 3.5, Anchor::End),
        (p.0 - d - w + 2.0, p.1 - d, Anchor::End),
        (p.0 - d - w + 2.0, p.1 + d + h - 2.0, Anchor::End),
        (p.0 - 0.5 * w, p.1 - d - 1.0, Anchor::Middle),
        (p.0 - 0.5 * w, p.1 + d + h, Anchor::Middle),
    ];
    let make = |(left, base, anchor): (f64, f64, Anchor)| {
        let bbox = Rect::new(left, base - 0.8 * h, w, h);
        let at = match anchor {
            Anchor::Start => (left, base),
            Anchor::End => (left + w, base),
            Anchor::Middle => (left + 0.5 * w, base),
        };
        Label {
            text: text.to_string(),
            at,
            anchor,
            bbox,
        }
    };
    let conflicts = |l: &Label| {
        let inside = l.bbox.x0 >= plot.x0 && l.bbox.x1 <= plot.x1 && l.bbox.y0 >= plot.y0 && l.bbox.y1 <= plot.y1;
        usize::from(!inside) * 100
            + avoid.iter().filter(|s| l.bbox.meets(s)).count()
            + 10 * placed.iter().filter(|o| o.bbox.overlaps(&l.bbox)).count()
    };
    candidates
        .into_iter()
        .map(make)
        .min_by_key(conflicts)
        .expect("eight candidates")
}

/// Draws one panel with its top-left corner at `origin`; returns its size
/// (grown by an outside legend and the notes).
fn draw_panel(
    svg: &mut Svg,
    c: &Chart,
    series: &[Series],
    origin: (f64, f64),
    left: f64,
) -> Result<(f64, f64), String> {
    let (x, y) = axes(c, series);
    let (y_ticks, _) = y_ticks_and_left(c, series);
    let top = top_px(&c.title);
    let (w, h) = c.size;
    let x_ticks = x.ticks((w - left - RIGHT_PX) / X_TICK_PX);
    if w - left - RIGHT_PX < 60.0 || h - top - BOTTOM_PX < 40.0 {
        return Err(format!("chart '{}' is too small to draw ({w} x {h} px)", c.title));
    }
    let plot = Rect::new(origin.0 + left, origin.1 + top, w - left - RIGHT_PX, h - top - BOTTOM_PX);
    let map = Map { plot, x, y };

    // Everything drawn, in pixels, as obstacles for labels and legend.
    let mut shapes: Vec<Shape> = Vec::new();
    let mut markers: Vec<(f64, f64, &Series)> = Vec::new();
    let mut bars: Vec<((f64, f64), (f64, f64), RGBColor)> = Vec::new();
    let mut curves: Vec<(Vec<(f64, f64)>, Stroke)> = Vec::new();
    let mut hidden: Vec<String> = Vec::new();
    let span = |a: f64, b: f64| (a.max(b) - a.min(b)).max(0.0);
    if c.diagonal {
        let (a, b) = (map.x.lo.max(map.y.lo), map.x.hi.min(map.y.hi));
        if let (Some(p), Some(q)) = (map.px(a, a), map.px(b, b)) {
            curves.push((vec![p, q], Stroke { dashed: true, ..Stroke::solid(REFERENCE, 1.2) }));
        }
    }
    for r in &c.references {
        if let (Some(p), Some(q)) = (map.px(map.x.lo, r.y), map.px(map.x.hi, r.y)) {
            let width = if r.label.is_empty() { 1.0 } else { 1.6 };
            curves.push((vec![p, q], Stroke { dashed: true, ..Stroke::solid(r.color, width) }));
        }
    }
    for s in series {
        if s.line {
            let pts: Vec<(f64, f64)> = s.points.iter().filter_map(|p| map.px(p.0, p.1)).collect();
            curves.push((pts, Stroke { dashed: s.dashed, ..Stroke::solid(s.color, 2.0) }));
            continue;
        }
        let mut small = Vec::new();
        for (i, p) in s.points.iter().enumerate() {
            let Some(at) = map.px(p.0, p.1) else { continue };
            markers.push((at.0, at.1, s));
            let mut bar_lengths = Vec::new();
            if p.2 > 0.0 {
                if let (Some(a), Some(b)) = (map.px(p.0, p.1 - p.2), map.px(p.0, p.1 + p.2)) {
                    bars.push((a, b, s.color));
                    bar_lengths.push(0.5 * span(a.1, b.1));
                }
            }
            let ex = s.x_err.get(i).copied().unwrap_or(0.0);
            if ex > 0.0 {
                if let (Some(a), Some(b)) = (map.px(p.0 - ex, p.1), map.px(p.0 + ex, p.1)) {
                    bars.push((a, b, s.color));
                    bar_lengths.push(0.5 * span(a.0, b.0));
                }
            }
            if bar_lengths.iter().any(|l| *l < MARKER_R + 1.0) {
                small.push(s.labels.get(i).filter(|l| !l.is_empty()).cloned().unwrap_or_else(|| format!("#{}", i + 1)));
            }
        }
        if !small.is_empty() {
            let who = if s.label.is_empty() { "some points".to_string() } else { s.label.clone() };
            hidden.push(format!("{who}: {}", small.join(", ")));
        }
    }
    for (pts, _) in &curves {
        shapes.extend(pts.windows(2).map(|w| Shape::Segment { a: w[0], b: w[1] }));
        if pts.len() == 1 {
            shapes.push(Shape::Segment { a: pts[0], b: pts[0] });
        }
    }
    for (a, b, _) in &bars {
        shapes.push(Shape::Segment { a: *a, b: *b });
        // The caps reach across the bar's ends.
        let cap = if (a.0 - b.0).abs() < 1e-9 { (CAP_PX, 0.0) } else { (0.0, CAP_PX) };
        for e in [a, b] {
            shapes.push(Shape::Segment { a: (e.0 - cap.0, e.1 - cap.1), b: (e.0 + cap.0, e.1 + cap.1) });
        }
    }
    shapes.extend(markers.iter().map(|m| Shape::Circle { cx: m.0, cy: m.1, r: MARKER_R + 1.0 }));

    let mut labels: Vec<Label> = Vec::new();
    for s in series.iter().filter(|s| !s.line) {
        for (p, text) in s.points.iter().zip(&s.labels) {
            let Some(at) = map.px(p.0, p.1).filter(|_| !text.is_empty()) else { continue };
            let l = place_label(text, at, plot, &shapes, &labels);
            labels.push(l);
        }
    }
    let mut obstacles = shapes.clone();
    obstacles.extend(labels.iter().map(|l| Shape::Box(l.bbox)));

    let mut entries: Vec<Entry> = Vec::new();
    for s in series.iter().filter(|s| !s.label.is_empty()) {
        let glyph = if s.line { Glyph::Line { dashed: s.dashed } } else { Glyph::Marker { hollow: s.hollow } };
        entries.push(Entry { glyph, color: s.color, label: s.label.clone() });
    }
    for r in c.references.iter().filter(|r| !r.label.is_empty()) {
        entries.push(Entry { glyph: Glyph::Line { dashed: true }, color: r.color, label: r.label.clone() });
    }
    if c.diagonal {
        entries.push(Entry { glyph: Glyph::Line { dashed: true }, color: REFERENCE, label: "y = x".into() });
    }
    entries.extend(c.entries.iter().cloned());
    let legend_at = if entries.is_empty() {
        None
    } else {
        Some(legend::place_inside(&entries, plot, &obstacles).unwrap_or_else(|| {
            let (lw, lh) = legend::size(&entries);
            Rect::new(plot.x1 + 14.0, plot.y0, lw, lh)
        }))
    };
    let panel_w = legend_at.map_or(w, |r| w.max(r.x1 + 8.0 - origin.0));

    let mut notes = c.notes.clone();
    if !hidden.is_empty() {
        notes.push(format!("Error bars smaller than the marker (drawn, hidden by it): {}.", hidden.join("; ")));
    }
    let notes: Vec<String> = notes.iter().flat_map(|n| wrap(n, panel_w - 24.0)).collect();

    let to_px = |t: &[(f64, String)], horizontal: bool| -> Vec<(f64, String)> {
        t.iter()
            .filter_map(|(v, l)| {
                let f = if horizontal { map.x.frac(*v) } else { map.y.frac(*v) }?;
                Some(if horizontal { (plot.x0 + f * plot.width(), l.clone()) } else { (plot.y1 - f * plot.height(), l.clone()) })
            })
            .collect()
    };
    let minor = |a: &Axis| a.minor_ticks().into_iter().map(|v| (v, String::new())).collect::<Vec<_>>();
    let mut xt = to_px(&x_ticks, true);
    xt.extend(to_px(&minor(&map.x), true));
    let mut yt = to_px(&y_ticks, false);
    yt.extend(to_px(&minor(&map.y), false));
    Frame {
        title: &c.title,
        x_desc: &c.x_desc,
        y_desc: &c.y_desc,
        x_ticks: xt,
        y_ticks: yt,
        x_grid: true,
    }
    .draw(svg, plot, (origin.0, origin.0 + w), origin.1);

    svg.group("data");
    for (pts, stroke) in &curves {
        svg.polyline(pts, *stroke);
    }
    for (a, b, color) in &bars {
        let s = Stroke::solid(*color, 1.2);
        svg.line(*a, *b, s);
        let cap = if (a.0 - b.0).abs() < 1e-9 { (CAP_PX, 0.0) } else { (0.0, CAP_PX) };
        for e in [a, b] {
            svg.line((e.0 - cap.0, e.1 - cap.1), (e.0 + cap.0, e.1 + cap.1), s);
        }
    }
    for (x, y, s) in &markers {
        svg.circle((*x, *y), MARKER_R, s.color, s.hollow);
    }
    svg.end_group();
    if !labels.is_empty() {
        svg.group("labels");
        for l in &labels {
            svg.text(l.at, &l.text, LABEL_FONT_PX, l.anchor, false, false);
        }
        svg.end_group();
    }
    if let Some(at) = legend_at {
        legend::draw(svg, &entries, at);
    }
    if !notes.is_empty() {
        svg.group("notes");
        for (i, n) in notes.iter().enumerate() {
            let y = origin.1 + h + 8.0 + NOTE_ROW_PX * i as f64;
            svg.text((origin.0 + 12.0, y), n, NOTE_FONT_PX, Anchor::Start, true, false);
        }
        svg.end_group();
    }
    let notes_h = if notes.is_empty() { 0.0 } else { NOTE_ROW_PX * notes.len() as f64 + 6.0 };
    Ok((panel_w, h + notes_h))
}

/// `text` broken at spaces into lines at most `max_px` wide.
pub(super) fn wrap(text: &str, max_px: f64) -> Vec<String> {
    let mut lines = vec![String::new()];
    for word in text.split(' ') {
        let last = lines.last_mut().expect("never empty");
        let candidate = if last.is_empty() { word.to_string() } else { format!("{last} {word}") };
        if width(&candidate, NOTE_FONT_PX) > max_px && !last.is_empty() {
            lines.push(word.to_string());
        } else {
            *last = candidate;
        }
    }
    lines
}
