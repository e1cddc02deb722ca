//! The path chart: one column per step of `diagnose`'s path, each step an
//! arrow from the previous step's value to its own, green and labelled
//! "falls" where it falls, red and labelled "rises" where it rises, grey
//! where the change is within the noise; the reduced chi-square on a log
//! axis (powers of ten) with the noise floor as a dashed line. Written as
//! SVG directly: the shared chart engine has no arrows per category.

use super::path::ChartStep;
use super::wording::{pct, stat, Change};
use std::fmt::Write;

// two side by side fit the page's 1204 px at their own size
const W: f64 = 590.0;
const H: f64 = 410.0;
const LEFT: f64 = 66.0;
const RIGHT: f64 = 24.0;
const TOP: f64 = 34.0;
const BOTTOM: f64 = 100.0;
const FALL: &str = "#1a7f37";
const RISE: &str = "#b2182b";
const FLAT: &str = "#777777";

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Metric {
    Mare,
    Chi2,
}

use crate::chart::escape_text as esc;
use crate::chart::{has_subscript, text_extent as extent};

/// The vertical axis: log10 for chi-square, linear from zero for MARE.
struct Scale {
    log: bool,
    lo: f64,
    hi: f64,
}

impl Scale {
    fn y(&self, v: f64) -> f64 {
        let (a, b, x) = if self.log {
            (self.lo.log10(), self.hi.log10(), v.max(self.lo).log10())
        } else {
            (self.lo, self.hi, v)
        };
        TOP + (H - TOP - BOTTOM) * (1.0 - (x - a) / (b - a))
    }

    /// `(value, label as SVG text content)`.
    fn ticks(&self) -> Vec<(f64, String)> {
        if self.log {
            let (a, b) = (
                self.lo.log10().ceil() as i32,
                self.hi.log10().floor() as i32,
            );
            let every = ((b - a) / 6 + 1).max(1);
            (a..=b)
                .filter(|k| (k - a) % every == 0)
                .map(|k| {
                    let label = match k {
                        0 => "1".to_string(),
                        1 => "10".to_string(),
                        _ => format!("10<tspan dy=\"-6\" font-size=\"9\">{k}</tspan>"),
                    };
                    (10f64.powi(k), label)
                })
                .collect()
        } else {
            let raw = (self.hi - self.lo) / 5.0;
            let mag = 10f64.powf(raw.log10().floor());
            let step = [1.0, 2.0, 5.0, 10.0]
                .iter()
                .map(|m| m * mag)
                .find(|s| *s >= raw)
                .unwrap_or(10.0 * mag);
            (0..)
                .map(|i| self.lo + step * i as f64)
                .take_while(|v| *v <= self.hi + 1e-9)
                .map(|v| (v, format!("{:.0} %", 100.0 * v)))
                .collect()
        }
    }
}

fn value(s: &ChartStep, m: Metric) -> Option<f64> {
    match m {
        Metric::Mare => Some(s.mare),
        Metric::Chi2 => s.chi2_reduced,
    }
    .filter(|v| v.is_finite() && *v > 0.0)
}

/// A point's value text as lines with their offsets from its baseline: one
/// line when it fits `room_px` (bold 11 px), else the word and the value on
/// two, stacked upwards or downwards, so that neighbouring values at one
/// height do not run into each other.
fn value_lines(text: &str, room_px: f64, upwards: bool) -> Vec<(String, f64)> {
    let fits = 1.1 * crate::chart::text_width(text, 11.0) <= room_px;
    match text.split_once(": ") {
        Some((word, value)) if !fits => {
            let (first, second) = if upwards { (-13.0, 0.0) } else { (0.0, 13.0) };
            vec![(format!("{word}:"), first), (value.to_string(), second)]
        }
        _ => vec![(text.to_string(), 0.0)],
    }
}

/// A label broken into lines of about `chars` characters, at spaces.
fn wrap(label: &str, chars: usize) -> Vec<String> {
    // A word wider than a line breaks after its hyphens
    // (`body-` / `confinement`): at 11 px an effect's name is wider than
    // its slot, and a label over the next one's is unreadable.
    let mut pieces: Vec<(String, bool)> = Vec::new();
    for word in label.split(' ') {
        if word.len() > chars && word.contains('-') {
            let parts: Vec<&str> = word.split_inclusive('-').collect();
            for (i, p) in parts.iter().enumerate() {
                pieces.push((p.to_string(), i == 0));
            }
        } else {
            pieces.push((word.to_string(), true));
        }
    }
    let mut lines: Vec<String> = vec![String::new()];
    for (word, spaced) in pieces {
        let cur = lines.last_mut().expect("one line");
        let glue = usize::from(spaced && !cur.is_empty());
        if !cur.is_empty() && cur.len() + glue + word.len() > chars {
            lines.push(word);
        } else {
            if glue == 1 {
                cur.push(' ');
            }
            cur.push_str(&word);
        }
    }
    lines.truncate(5);
    lines
}

/// The chart of `steps` for one metric; `floor` draws the noise floor (and
/// is the chi-square's noise); `mare_noise` is the MARE's, the same the
/// tables judge a change by, so chart and table never disagree.
pub fn chart(
    steps: &[ChartStep],
    m: Metric,
    floor: Option<f64>,
    mare_noise: f64,
) -> crate::chart::PlotResult {
    let vals: Vec<f64> = steps.iter().filter_map(|s| value(s, m)).collect();
    if vals.is_empty() {
        return Err(crate::chart::ChartError::NoFiniteValue { what: "step" });
    }
    let floor = floor.filter(|f| f.is_finite() && *f > 0.0 && m == Metric::Chi2);
    let all = vals.iter().copied().chain(floor);
    let (lo, hi) = all.fold((f64::INFINITY, 0.0f64), |(a, b), v| (a.min(v), b.max(v)));
    let scale = match m {
        Metric::Chi2 => Scale {
            log: true,
            // room below the lowest point for its label
            lo: 10f64.powf((lo / 3.0).log10().floor()),
            hi: 10f64.powf((hi * 1.5).log10().ceil()),
        },
        Metric::Mare => Scale {
            log: false,
            lo: 0.0,
            hi: hi * 1.15,
        },
    };
    let show = |v: f64| match m {
        Metric::Mare => pct(v),
        Metric::Chi2 => stat(Some(v)),
    };
    let noise = match m {
        Metric::Chi2 => floor.unwrap_or(0.0),
        Metric::Mare => mare_noise,
    };
    let n = steps.len().max(1) as f64;
    let slot = (W - LEFT - RIGHT) / n;
    let cx = |i: usize| LEFT + slot * (i as f64 + 0.5);
    let mut s = String::new();
    let _ = write!(
        s,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{W}\" height=\"{H}\" viewBox=\"0 0 {W} {H}\" \
         font-family=\"'DejaVu Sans', 'Liberation Sans', Helvetica, Arial, sans-serif\" font-size=\"11\"><rect width=\"{W}\" height=\"{H}\" fill=\"white\"/>"
    );
    let title = match m {
        Metric::Mare => "MARE along the path",
        Metric::Chi2 => "Reduced χ² along the path",
    };
    let _ = write!(
        s,
        "<text x=\"{}\" y=\"20\" text-anchor=\"middle\" font-size=\"15\">{title}</text>",
        W / 2.0
    );
    // axes and ticks
    let (y_top, y_bot) = (TOP, H - BOTTOM);
    let _ = write!(
        s,
        "<path d=\"M{LEFT},{y_top}V{y_bot}H{}\" stroke=\"#333\" fill=\"none\"/>",
        W - RIGHT
    );
    for (v, label) in scale.ticks() {
        let y = scale.y(v);
        let _ = write!(
            s,
            "<line x1=\"{}\" x2=\"{}\" y1=\"{y:.1}\" y2=\"{y:.1}\" stroke=\"#eee\"/>\
             <line x1=\"{}\" x2=\"{LEFT}\" y1=\"{y:.1}\" y2=\"{y:.1}\" stroke=\"#333\"/>\
             <text x=\"{}\" y=\"{:.1}\" text-anchor=\"end\">{label}</text>",
            LEFT + 1.0,
            W - RIGHT,
            LEFT - 4.0,
            LEFT - 7.0,
            y + 4.0
        );
    }
    let y_desc = match m {
        Metric::Mare => "MARE",
        Metric::Chi2 => "reduced χ²",
    };
    let _ = write!(
        s,
        "<text transform=\"translate(14,{:.1}) rotate(-90)\" text-anchor=\"middle\" font-size=\"12\">{y_desc}</text>",
        (y_top + y_bot) / 2.0
    );
    if let Some(f) = floor {
        let y = scale.y(f);
        let _ = write!(
            s,
            "<line class=\"noise-floor\" x1=\"{LEFT}\" x2=\"{}\" y1=\"{y:.1}\" y2=\"{y:.1}\" stroke=\"#444\" \
             stroke-width=\"1.5\" stroke-dasharray=\"6 4\"/>\
             <text x=\"{}\" y=\"{:.1}\" text-anchor=\"end\" fill=\"#444\">noise floor {}</text>",
            W - RIGHT,
            W - RIGHT - 4.0,
            y - 5.0,
            esc(&stat(Some(f)))
        );
    }
    // steps
    let mut prev: Option<(usize, f64)> = None;
    for (i, st) in steps.iter().enumerate() {
        let x = cx(i);
        // A label is drawn as written (`body.E_x`, `pitch_angle_deg`: names,
        // not notation), but the engine's text checks read `_x` as a
        // subscript, so such a line pushes the next one down by its depth.
        // 11 px, the page's smallest text (6.5 px a character on average).
        let mut y_line = y_bot + 16.0;
        for line in wrap(&st.label, (slot / 6.5) as usize) {
            let _ = write!(
                s,
                "<text x=\"{x:.1}\" y=\"{y_line:.1}\" text-anchor=\"middle\" font-size=\"11\">{}</text>",
                esc(&line)
            );
            let (_, below) = extent(11.0, has_subscript(&line));
            y_line += 13.5 + (below - extent(11.0, false).1);
        }
        let Some(v) = value(st, m) else { continue };
        let y = scale.y(v);
        let (color, word) = match prev {
            None => ("#333333", None),
            Some((_, p)) => match Change::of(p, v, noise) {
                Change::Falls => (FALL, Some("falls")),
                Change::Rises => (RISE, Some("rises")),
                Change::Flat => (FLAT, Some("no real change")),
            },
        };
        if let Some((pi, p)) = prev {
            let yp = scale.y(p);
            let _ = write!(
                s,
                "<line x1=\"{:.1}\" x2=\"{x:.1}\" y1=\"{yp:.1}\" y2=\"{yp:.1}\" stroke=\"#999\" stroke-dasharray=\"2 3\"/>",
                cx(pi)
            );
            if (y - yp).abs() > 9.0 {
                let dir = if y > yp { 1.0 } else { -1.0 };
                let _ = write!(
                    s,
                    "<line x1=\"{x:.1}\" x2=\"{x:.1}\" y1=\"{yp:.1}\" y2=\"{:.1}\" stroke=\"{color}\" stroke-width=\"3\"/>\
                     <path d=\"M{:.1},{:.1}L{:.1},{:.1}L{:.1},{:.1}Z\" fill=\"{color}\"/>",
                    y - dir * 8.0,
                    x - 6.0,
                    y - dir * 10.0,
                    x + 6.0,
                    y - dir * 10.0,
                    x,
                    y
                );
            }
        }
        let _ = write!(
            s,
            "<circle cx=\"{x:.1}\" cy=\"{y:.1}\" r=\"4.5\" fill=\"{color}\"/>"
        );
        // value and word beside the point, on the side away from the arrow
        let above = prev.is_none_or(|(_, p)| v >= p);
        // below the point unless that reaches the axis: then left of it
        // (the dotted line from the step before runs at that step's level)
        let (tx, ty, anchor) = if above {
            (x, y - 10.0, "middle")
        } else if y + 16.0 > y_bot - 2.0 {
            (x - 9.0, y + 4.0, "end")
        } else {
            (x, y + 16.0, "middle")
        };
        let text = format!(
            "{}{}",
            word.map(|w| format!("{w}: ")).unwrap_or_default(),
            show(v)
        );
        // centred: the step's slot; left of the point: the half slot
        // between it and the previous step's centred label
        let (room, upwards) = if anchor == "end" {
            (0.5 * slot - 12.0, true)
        } else {
            (slot - 8.0, above)
        };
        for (line, dy) in value_lines(&text, room, upwards) {
            let _ = write!(
                s,
                "<text x=\"{tx:.1}\" y=\"{:.1}\" text-anchor=\"{anchor}\" font-weight=\"600\" fill=\"{color}\">{}</text>",
                ty + dy,
                esc(&line)
            );
        }
        prev = Some((i, v));
    }
    s.push_str("</svg>");
    Ok(s)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_name_wider_than_its_line_breaks_after_a_hyphen() {
        assert_eq!(wrap("+ body-confinement", 15), ["+ body-", "confinement"]);
        assert_eq!(wrap("+ backflow", 15), ["+ backflow"]);
        assert_eq!(wrap("start", 15), ["start"]);
    }

    fn step(label: &str, mare: f64, chi2: f64) -> ChartStep {
        ChartStep {
            label: label.into(),
            what: String::new(),
            fitted: 0,
            mare,
            cv_mare: None,
            chi2_reduced: Some(chi2),
        }
    }

    /// The y of the text that starts with `word`.
    fn text_y(svg: &str, word: &str) -> f64 {
        let at = svg.find(&format!(">{word}")).expect("the label");
        let head = &svg[svg[..at].rfind("<text").unwrap()..at];
        let y = &head[head.find(" y=\"").unwrap() + 4..];
        y[..y.find('"').unwrap()].parse().unwrap()
    }

    #[test]
    fn a_value_at_the_bottom_keeps_its_label_above_the_category_names() {
        let steps = [step("start", 2.9, 8.2e6), step("+ a", 0.44, 1.02e5)];
        for (m, word) in [
            (Metric::Chi2, "falls: 1.02e5"),
            (Metric::Mare, "falls: 44.0 %"),
        ] {
            let svg = chart(&steps, m, None, 0.0).unwrap();
            assert!(text_y(&svg, word) < H - BOTTOM, "{m:?}: {word} on the axis");
        }
    }
}
