//! Reads an SVG written by this engine back and checks that no legend box
//! covers data: markers (circles), error bars and reference lines (lines),
//! curves (polyline segments) and bars (rects) of every `data` group.

use super::geom::{Rect, Shape};

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
