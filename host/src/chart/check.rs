//! Reads an SVG written by this engine back and checks that no legend box
//! covers data: markers (circles), error bars and reference lines (lines),
//! curves (polyline segments) and bars (rects) of every `data` group; and
//! that no two texts overlap or leave the drawing ([`text_clear`]).

use super::geom::{Rect, Shape};
use super::svg_text::{extent, has_subscript, width};

/// Clearance the checker demands (a little less than the placement keeps).
const CHECK_MARGIN_PX: f64 = 2.0;

/// The attribute `name` of the tag text `tag` as a number.
fn attr(tag: &str, name: &str) -> Option<f64> {
    let key = format!(" {name}=\"");
    let start = tag.find(&key)? + key.len();
    let end = tag[start..].find('"')? + start;
    tag[start..end].trim().parse().ok()
}

fn attr_str<'a>(tag: &'a str, name: &str) -> Option<&'a str> {
    let key = format!(" {name}=\"");
    let start = tag.find(&key)? + key.len();
    let end = tag[start..].find('"')? + start;
    Some(&tag[start..end])
}

/// The bodies of every `<g class="{class}">` group (groups do not nest).
fn groups<'a>(svg: &'a str, class: &str) -> Vec<&'a str> {
    let open = format!("<g class=\"{class}\">");
    let mut out = Vec::new();
    let mut rest = svg;
    while let Some(i) = rest.find(&open) {
        let body = &rest[i + open.len()..];
        let end = body.find("</g>").unwrap_or(body.len());
        out.push(&body[..end]);
        rest = &body[end..];
    }
    out
}

/// Every element tag `<name ...>` in `body`.
fn tags<'a>(body: &'a str, name: &str) -> Vec<&'a str> {
    let open = format!("<{name} ");
    body.match_indices(&open)
        .map(|(i, _)| {
            let t = &body[i..];
            &t[..t.find('>').map_or(t.len(), |e| e + 1)]
        })
        .collect()
}

fn shapes(body: &str) -> Result<Vec<Shape>, String> {
    let bad = |t: &str| format!("unreadable element in a data group: {t}");
    let mut out = Vec::new();
    for t in tags(body, "circle") {
        let (cx, cy, r) = (attr(t, "cx"), attr(t, "cy"), attr(t, "r"));
        out.push(Shape::Circle {
            cx: cx.ok_or_else(|| bad(t))?,
            cy: cy.ok_or_else(|| bad(t))?,
            r: r.ok_or_else(|| bad(t))?,
        });
    }
    for t in tags(body, "line") {
        let v: Option<Vec<f64>> = ["x1", "y1", "x2", "y2"]
            .iter()
            .map(|n| attr(t, n))
            .collect();
        let v = v.ok_or_else(|| bad(t))?;
        out.push(Shape::Segment {
            a: (v[0], v[1]),
            b: (v[2], v[3]),
        });
    }
    for t in tags(body, "polyline") {
        let pts: Option<Vec<(f64, f64)>> = attr_str(t, "points")
            .ok_or_else(|| bad(t))?
            .split_whitespace()
            .map(|p| {
                let (x, y) = p.split_once(',')?;
                Some((x.parse().ok()?, y.parse().ok()?))
            })
            .collect();
        let pts = pts.ok_or_else(|| bad(t))?;
        out.extend(pts.windows(2).map(|w| Shape::Segment { a: w[0], b: w[1] }));
        if let [p] = pts[..] {
            out.push(Shape::Segment { a: p, b: p });
        }
    }
    for t in tags(body, "rect") {
        let v: Option<Vec<f64>> = ["x", "y", "width", "height"]
            .iter()
            .map(|n| attr(t, n))
            .collect();
        let v = v.ok_or_else(|| bad(t))?;
        out.push(Shape::Box(Rect::new(v[0], v[1], v[2], v[3])));
    }
    Ok(out)
}

/// `Ok` when no legend box of `svg` meets any data drawn in it; the error
/// names the legend and the first element it covers.
pub fn legend_clear(svg: &str) -> Result<(), String> {
    let data: Vec<Shape> = groups(svg, "data")
        .into_iter()
        .map(shapes)
        .collect::<Result<Vec<_>, _>>()?
        .into_iter()
        .flatten()
        .collect();
    for legend in groups(svg, "legend") {
        let t = tags(legend, "rect")
            .into_iter()
            .next()
            .ok_or("a legend group without its box")?;
        let v: Option<Vec<f64>> = ["x", "y", "width", "height"]
            .iter()
            .map(|n| attr(t, n))
            .collect();
        let v = v.ok_or_else(|| format!("unreadable legend box: {t}"))?;
        let box_ = Rect::new(v[0], v[1], v[2], v[3]);
        if let Some(s) = data.iter().find(|s| box_.inflate(CHECK_MARGIN_PX).meets(s)) {
            return Err(format!(
                "the legend at ({:.0}, {:.0}) size {:.0} x {:.0} covers {s:?}",
                v[0], v[1], v[2], v[3]
            ));
        }
    }
    Ok(())
}

/// A `<text>` element's content back in code form (`Ω_b`), entities undone.
fn code_text(inner: &str) -> String {
    let mut out = String::new();
    let mut rest = inner;
    while let Some(i) = rest.find("<tspan") {
        out.push_str(&rest[..i]);
        let tag_end = rest[i..].find('>').map_or(rest.len(), |e| i + e + 1);
        let mark = if rest[i..tag_end].contains("\"sub\"") {
            '_'
        } else {
            '^'
        };
        let close = rest[tag_end..]
            .find("</tspan>")
            .map_or(rest.len(), |e| tag_end + e);
        out.push(mark);
        out.push_str(&rest[tag_end..close]);
        rest = rest.get(close + "</tspan>".len()..).unwrap_or("");
    }
    out.push_str(rest);
    out.replace("&lt;", "<")
        .replace("&gt;", ">")
        .replace("&quot;", "\"")
        .replace("&#39;", "'")
        .replace("&amp;", "&")
}

/// Every `<text>` of `body` with the box it is estimated to cover, from
/// the same font model the layout uses ([`width`], [`extent`]).
/// Texts without their own `font-size` take `inherited` (the root's).
fn text_boxes(body: &str, inherited: Option<f64>) -> Result<Vec<(String, Rect)>, String> {
    let mut out = Vec::new();
    for (i, _) in body.match_indices("<text ") {
        let t = &body[i..];
        let open_end = t.find('>').ok_or("an unclosed <text> tag")?;
        let tag = &t[..open_end];
        let inner = &t[open_end + 1..t.find("</text>").ok_or("a <text> without its end")?];
        let bad = || format!("unreadable text element: {tag}");
        // `transform="translate(x,y) rotate(-90)"` places it without x, y.
        let moved = attr_str(tag, "transform")
            .and_then(|t| t.strip_prefix("translate("))
            .and_then(|t| t.split_once(')'))
            .and_then(|(xy, _)| xy.split_once(','))
            .and_then(|(x, y)| Some((x.trim().parse().ok()?, y.trim().parse().ok()?)));
        let (x, y) = match moved {
            Some((x, y)) => (Some(x), Some(y)),
            None => (attr(tag, "x"), attr(tag, "y")),
        };
        let size = attr(tag, "font-size").or(inherited);
        let (x, y, size) = (
            x.ok_or_else(bad)?,
            y.ok_or_else(bad)?,
            size.ok_or_else(bad)?,
        );
        let text = code_text(inner);
        // DejaVu Sans Bold runs about a tenth wider than the book face.
        let bold = matches!(attr_str(tag, "font-weight"), Some("600" | "700" | "bold"));
        let w = width(&text, size) * if bold { 1.1 } else { 1.0 };
        let (above, below) = extent(size, has_subscript(&text));
        let before = match attr_str(tag, "text-anchor") {
            Some("middle") => 0.5 * w,
            Some("end") => w,
            _ => 0.0,
        };
        // rotate(-90) about the anchor: the text runs upwards, its ascent
        // to the left of the baseline.
        let rect = if tag.contains("rotate(-90") {
            Rect::new(x - above, y - (w - before), above + below, w)
        } else {
            Rect::new(x - before, y - above, w, above + below)
        };
        out.push((text, rect));
    }
    Ok(out)
}

/// `Ok` when no two texts of `svg` overlap (tick labels, axis titles,
/// point labels, legend, notes), every text stays inside the drawing, and
/// every legend text inside its legend's box; the error names the texts.
/// Boxes come from the layout's font model (DejaVu Sans), so this checks
/// the layout rule, not a browser's rendering.
pub fn text_clear(svg: &str) -> Result<(), String> {
    let root = tags(svg, "svg").first().copied().unwrap_or("");
    let size = attr(root, "width").zip(attr(root, "height"));
    let font = attr(root, "font-size");
    let texts = text_boxes(svg, font)?;
    for (i, (a, ra)) in texts.iter().enumerate() {
        if let Some((w, h)) = size {
            if ra.x0 < 0.0 || ra.y0 < 0.0 || ra.x1 > w || ra.y1 > h {
                return Err(format!("'{a}' at {ra:?} leaves the {w} x {h} drawing"));
            }
        }
        // Touching boxes are fine: the font model already holds each
        // glyph's full ascent and descent.
        if let Some((b, rb)) = texts[i + 1..]
            .iter()
            .find(|(_, rb)| ra.inflate(-TEXT_SLACK_PX).overlaps(rb))
        {
            return Err(format!("'{a}' at {ra:?} overlaps '{b}' at {rb:?}"));
        }
    }
    for legend in groups(svg, "legend") {
        let Some(t) = tags(legend, "rect").into_iter().next() else {
            return Err("a legend group without its box".into());
        };
        let x1 = attr(t, "x").unwrap_or(0.0) + attr(t, "width").unwrap_or(0.0);
        for (text, r) in text_boxes(legend, font)? {
            if r.x1 > x1 {
                return Err(format!("legend text '{text}' runs out of its box"));
            }
        }
    }
    Ok(())
}

/// Overlap a text box may have with another before it counts (half a px:
/// coordinates are written to 0.1 px).
const TEXT_SLACK_PX: f64 = 0.5;
