//! One chart panel drawn: its axes and frame, the data with error bars
//! and point labels, the legend where it covers nothing, and the notes
//! (among them which error bars the markers hide).

use super::builder::{axes, y_ticks_and_left, Chart, Map, REFERENCE, X_TICK_PX};
use super::frame::{top_px, Frame, BOTTOM_PX, RIGHT_PX};
use super::geom::{Rect, Shape};
use super::labels::{place_label, wrap, Label, LABEL_FONT_PX, NOTE_FONT_PX};
use super::legend::{self, Entry, Glyph};
use super::series::Series;
use super::svg::{Anchor, Stroke, Svg};
use super::ticks::Axis;
use super::Rgb;

const MARKER_R: f64 = 4.0;
const CAP_PX: f64 = 3.0;
const NOTE_ROW_PX: f64 = 15.0;

/// An error bar's two ends in pixels and its colour.
type ErrorBar = ((f64, f64), (f64, f64), Rgb);

/// What a panel draws, in pixels, and everything drawn as obstacles for
/// labels and legend.
struct Geometry<'a> {
    shapes: Vec<Shape>,
    markers: Vec<(f64, f64, &'a Series)>,
    bars: Vec<ErrorBar>,
    curves: Vec<(Vec<(f64, f64)>, Stroke)>,
    /// Which error bars the markers hide, for the note.
    hidden: Vec<String>,
}

fn geometry<'a>(c: &Chart, series: &'a [Series], map: &Map) -> Geometry<'a> {
    let mut shapes: Vec<Shape> = Vec::new();
    let mut markers: Vec<(f64, f64, &Series)> = Vec::new();
    let mut bars: Vec<ErrorBar> = Vec::new();
    let mut curves: Vec<(Vec<(f64, f64)>, Stroke)> = Vec::new();
    let mut hidden: Vec<String> = Vec::new();
    let span = |a: f64, b: f64| (a.max(b) - a.min(b)).max(0.0);
    if c.diagonal {
        let (a, b) = (map.x.lo.max(map.y.lo), map.x.hi.min(map.y.hi));
        if let (Some(p), Some(q)) = (map.px(a, a), map.px(b, b)) {
            curves.push((
                vec![p, q],
                Stroke {
                    dashed: true,
                    ..Stroke::solid(REFERENCE, 1.2)
                },
            ));
        }
    }
    for r in &c.references {
        if let (Some(p), Some(q)) = (map.px(map.x.lo, r.y), map.px(map.x.hi, r.y)) {
            let width = if r.label.is_empty() { 1.0 } else { 1.6 };
            curves.push((
                vec![p, q],
                Stroke {
                    dashed: true,
                    ..Stroke::solid(r.color, width)
                },
            ));
        }
    }
    for s in series {
        if s.line {
            let dx = s.dodge * map.plot.width();
            let pts: Vec<(f64, f64)> = s
                .points
                .iter()
                .filter_map(|p| map.px(p.0, p.1).map(|(x, y)| (x + dx, y)))
                .collect();
            curves.push((
                pts,
                Stroke {
                    dashed: s.dashed,
                    ..Stroke::solid(s.color, 2.0)
                },
            ));
            continue;
        }
        // Points whose bars the marker hides, by bar direction.
        let mut small: [Vec<String>; 2] = [Vec::new(), Vec::new()];
        let mut with_bars = [0usize; 2];
        let dx = s.dodge * map.plot.width();
        let px = |x: f64, y: f64| map.px(x, y).map(|(a, b)| (a + dx, b));
        for (i, p) in s.points.iter().enumerate() {
            let Some(at) = px(p.0, p.1) else { continue };
            markers.push((at.0, at.1, s));
            let name = || {
                s.labels
                    .get(i)
                    .filter(|l| !l.is_empty())
                    .or_else(|| s.names.get(i).filter(|l| !l.is_empty()))
                    .cloned()
                    .unwrap_or_else(|| format!("point {}", i + 1))
            };
            if p.2 > 0.0 {
                if let (Some(a), Some(b)) = (px(p.0, p.1 - p.2), px(p.0, p.1 + p.2)) {
                    bars.push((a, b, s.color));
                    with_bars[1] += 1;
                    if 0.5 * span(a.1, b.1) < MARKER_R + 1.0 {
                        small[1].push(name());
                    }
                }
            }
            let ex = s.x_err.get(i).copied().unwrap_or(0.0);
            if ex > 0.0 {
                if let (Some(a), Some(b)) = (px(p.0 - ex, p.1), px(p.0 + ex, p.1)) {
                    bars.push((a, b, s.color));
                    with_bars[0] += 1;
                    if 0.5 * span(a.0, b.0) < MARKER_R + 1.0 {
                        small[0].push(name());
                    }
                }
            }
        }
        for ((dir, who), n) in ["horizontal", "vertical"].iter().zip(&small).zip(with_bars) {
            if who.is_empty() {
                continue;
            }
            let who = if who.len() == n && n > 2 {
                vec!["all points".to_string()]
            } else {
                who.clone()
            };
            let series = if s.label.is_empty() {
                String::new()
            } else {
                format!(" ({})", s.label)
            };
            hidden.push(format!("{dir} bars of {}{series}", who.join(", ")));
        }
    }
    for (pts, _) in &curves {
        shapes.extend(pts.windows(2).map(|w| Shape::Segment { a: w[0], b: w[1] }));
        if pts.len() == 1 {
            shapes.push(Shape::Segment {
                a: pts[0],
                b: pts[0],
            });
        }
    }
    for (a, b, _) in &bars {
        shapes.push(Shape::Segment { a: *a, b: *b });
        // The caps reach across the bar's ends.
        let cap = if (a.0 - b.0).abs() < 1e-9 {
            (CAP_PX, 0.0)
        } else {
            (0.0, CAP_PX)
        };
        for e in [a, b] {
            shapes.push(Shape::Segment {
                a: (e.0 - cap.0, e.1 - cap.1),
                b: (e.0 + cap.0, e.1 + cap.1),
            });
        }
    }
    shapes.extend(markers.iter().map(|m| Shape::Circle {
        cx: m.0,
        cy: m.1,
        r: MARKER_R + 1.0,
    }));

    Geometry {
        shapes,
        markers,
        bars,
        curves,
        hidden,
    }
}

/// The legend's entries of a panel: its labelled series, reference
/// lines, the diagonal and the extra entries, in that order.
pub(super) fn entries_of(c: &Chart, series: &[Series]) -> Vec<Entry> {
    let mut entries: Vec<Entry> = Vec::new();
    for s in series.iter().filter(|s| !s.label.is_empty()) {
        let glyph = if s.line {
            Glyph::Line { dashed: s.dashed }
        } else {
            Glyph::Marker { hollow: s.hollow }
        };
        entries.push(Entry {
            glyph,
            color: s.color,
            label: s.label.clone(),
        });
    }
    for r in c.references.iter().filter(|r| !r.label.is_empty()) {
        entries.push(Entry {
            glyph: Glyph::Line { dashed: true },
            color: r.color,
            label: r.label.clone(),
        });
    }
    if c.diagonal {
        entries.push(Entry {
            glyph: Glyph::Line { dashed: true },
            color: REFERENCE,
            label: "y = x".into(),
        });
    }
    entries.extend(c.entries.iter().cloned());
    entries
}

/// Draws one panel with its top-left corner at `origin`; returns its size
/// (grown by an outside legend and the notes).
pub fn draw_panel(
    svg: &mut Svg,
    c: &Chart,
    series: &[Series],
    origin: (f64, f64),
    left: f64,
) -> Result<(f64, f64), super::ChartError> {
    let (x, y) = axes(c, series);
    let (y_ticks, _) = y_ticks_and_left(c, series);
    let top = top_px(&c.title);
    let (w, h) = c.size;
    let x_ticks = x.ticks((w - left - RIGHT_PX) / X_TICK_PX);
    if w - left - RIGHT_PX < 60.0 || h - top - BOTTOM_PX < 40.0 {
        return Err(super::ChartError::PanelTooSmall {
            title: c.title.clone(),
            width_px: w,
            height_px: h,
        });
    }
    let plot = Rect::new(
        origin.0 + left,
        origin.1 + top,
        w - left - RIGHT_PX,
        h - top - BOTTOM_PX,
    );
    let map = Map { plot, x, y };

    let Geometry {
        shapes,
        markers,
        bars,
        curves,
        hidden,
    } = geometry(c, series, &map);

    let mut labels: Vec<Label> = Vec::new();
    for s in series.iter().filter(|s| !s.line) {
        for (p, text) in s.points.iter().zip(&s.labels) {
            let Some(at) = map
                .px(p.0, p.1)
                .map(|(x, y)| (x + s.dodge * plot.width(), y))
                .filter(|_| !text.is_empty())
            else {
                continue;
            };
            let l = place_label(MARKER_R, text, at, plot, &shapes, &labels);
            labels.push(l);
        }
    }
    let mut obstacles = shapes.clone();
    obstacles.extend(labels.iter().map(|l| Shape::Box(l.bbox)));

    let entries = entries_of(c, series);
    let legend_at = if entries.is_empty() || !c.legend {
        None
    } else {
        Some(
            legend::place_inside(&entries, plot, &obstacles).unwrap_or_else(|| {
                let (lw, lh) = legend::size(&entries);
                Rect::new(plot.x1 + 14.0, plot.y0, lw, lh)
            }),
        )
    };
    let panel_w = legend_at.map_or(w, |r| w.max(r.x1 + 8.0 - origin.0));

    let mut notes = c.notes.clone();
    if !hidden.is_empty() && c.hidden_note {
        notes.push(format!(
            "Smaller than the marker (drawn, hidden by it): {}.",
            hidden.join("; ")
        ));
    }
    let notes: Vec<String> = notes.iter().flat_map(|n| wrap(n, panel_w - 24.0)).collect();

    let to_px = |t: &[(f64, String)], horizontal: bool| -> Vec<(f64, String)> {
        t.iter()
            .filter_map(|(v, l)| {
                let f = if horizontal {
                    map.x.frac(*v)
                } else {
                    map.y.frac(*v)
                }?;
                Some(if horizontal {
                    (plot.x0 + f * plot.width(), l.clone())
                } else {
                    (plot.y1 - f * plot.height(), l.clone())
                })
            })
            .collect()
    };
    let minor = |a: &Axis| {
        a.minor_ticks()
            .into_iter()
            .map(|v| (v, String::new()))
            .collect::<Vec<_>>()
    };
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
        left_of_plot: left,
    }
    .draw(svg, plot, origin.1);

    svg.group("data");
    for (pts, stroke) in &curves {
        svg.polyline(pts, *stroke);
    }
    for (a, b, color) in &bars {
        let s = Stroke::solid(*color, 1.2);
        svg.line(*a, *b, s);
        let cap = if (a.0 - b.0).abs() < 1e-9 {
            (CAP_PX, 0.0)
        } else {
            (0.0, CAP_PX)
        };
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
            let y = origin.1 + h + 12.0 + NOTE_ROW_PX * i as f64;
            svg.text(
                (origin.0 + 12.0, y),
                n,
                NOTE_FONT_PX,
                Anchor::Start,
                true,
                false,
            );
        }
        svg.end_group();
    }
    let notes_h = if notes.is_empty() {
        0.0
    } else {
        NOTE_ROW_PX * notes.len() as f64 + 10.0
    };
    Ok((panel_w, h + notes_h))
}
