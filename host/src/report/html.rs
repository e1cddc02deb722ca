//! The page's frame: one self-contained HTML document (inline CSS and SVG,
//! no external resource), readable on a laptop screen and printable
//! (figures and tables never split across pages), and the small HTML
//! helpers the sections share.

/// The stylesheet: screen first, then print.
const STYLE: &str = "\
body{font-family:system-ui,-apple-system,'Segoe UI',Roboto,sans-serif;font-size:15px;line-height:1.5;\
max-width:1240px;margin:1.5em auto;padding:0 1.2em;color:#1d1d1d}\
h1{font-size:1.7em;margin-bottom:.2em}h2{margin-top:1.8em;border-bottom:2px solid #ddd;padding-bottom:.15em}\
h3{margin-bottom:.3em}p,li{max-width:62em}\
table{border-collapse:collapse;margin:.6em 0;font-size:.9em;font-variant-numeric:tabular-nums}\
td,th{padding:3px 9px;border-bottom:1px solid #ddd;text-align:right;vertical-align:top;white-space:nowrap}\
td.l,th.l{white-space:normal}\
th{background:#f3f3f3;white-space:normal}td.l:first-child{white-space:nowrap}td.l,th.l{text-align:left}\
code{background:#f3f3f3;padding:1px 4px;border-radius:3px;font-size:.92em}\
figure{margin:1em 0;break-inside:avoid;page-break-inside:avoid}\
figcaption{font-size:.9em;color:#333;max-width:62em;margin-top:.3em}\
.grid{display:grid;gap:10px 16px;grid-template-columns:repeat(var(--cols,2),minmax(0,max-content));justify-content:start}\
.grid svg{max-width:100%;height:auto;display:block}.fig-legend{margin:0 0 6px}figure>svg{max-width:100%;height:auto}\
.rise{color:#b2182b;font-weight:600}.fall{color:#1a7f37;font-weight:600}.flat{color:#666}\
.note{color:#555;font-size:.9em}.err{color:#b00}.verdict{background:#fff7e6;border-left:4px solid #e6a23c;padding:.5em .9em}\
.toc{columns:2;font-size:.95em}\
@media (max-width:900px){.grid{grid-template-columns:repeat(2,minmax(0,max-content))}\
.flow .grid{grid-template-rows:repeat(var(--rows),auto);grid-auto-flow:column}}\
@media print{body{max-width:none;margin:0;padding:0;font-size:10pt}h2{break-after:avoid;page-break-after:avoid}\
table,figure,.verdict{break-inside:avoid;page-break-inside:avoid}.toc{display:none}\
.grid{grid-template-columns:repeat(2,minmax(0,max-content))}.flow .grid{grid-template-rows:repeat(var(--rows),auto);grid-auto-flow:column}\
@page{size:A4;margin:14mm}}";

pub fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// Text in physics notation as HTML: escaped, `Omega_b` as Ω<sub>b</sub>,
/// `x^2` as x<sup>2</sup> (the same runs the charts draw).
pub fn rich(s: &str) -> String {
    crate::chart::notation_runs(&crate::chart::notation(s))
        .into_iter()
        .map(|(t, shift)| match shift {
            0 => escape(&t),
            -1 => format!("<sub>{}</sub>", escape(&t)),
            _ => format!("<sup>{}</sup>", escape(&t)),
        })
        .collect()
}

/// A chart, or a visible note where it failed.
pub fn svg_or_note(r: &Result<String, String>) -> String {
    match r {
        Ok(svg) => svg.clone(),
        Err(e) => format!("<p class=\"err\">chart failed: {}</p>", escape(e)),
    }
}

/// A figure of charts in a grid of `columns`, with its caption (HTML).
pub fn figure(
    id: &str,
    charts: &[Result<String, String>],
    columns: usize,
    caption: &str,
) -> String {
    figure_in(id, "", charts, columns, caption)
}

/// [`figure`] for panels given row by row that, on paper and on narrow
/// screens (two columns), are laid out column by column instead, so that
/// each printed row keeps one column of the wide layout together (Fig. 4:
/// each group's U beside its Omega_b).
/// `legend`, one for every panel, is drawn above the grid so that no panel
/// is widened by it.
pub fn figure_flow(
    id: &str,
    legend: Option<&Result<String, String>>,
    charts: &[Result<String, String>],
    columns: usize,
    caption: &str,
) -> String {
    let rows = charts.len().div_ceil(2).max(1);
    let attrs = if columns == rows {
        format!(" class=\"flow\" style=\"--rows:{rows}\"")
    } else {
        String::new()
    };
    let mut h = figure_in(id, &attrs, charts, columns, caption);
    if let Some(l) = legend {
        let at = h
            .find("<div class=\"grid\"")
            .expect("figure_in writes a grid");
        h.insert_str(
            at,
            &format!("<div class=\"fig-legend\">{}</div>", svg_or_note(l)),
        );
    }
    h
}

fn figure_in(
    id: &str,
    attrs: &str,
    charts: &[Result<String, String>],
    columns: usize,
    caption: &str,
) -> String {
    // Each SVG is shown at its own size (its ticks read at the size they
    // were drawn), shrunk only when the columns do not fit.
    let mut h = format!(
        "<figure id=\"{id}\"{attrs}><div class=\"grid\" style=\"--cols:{}\">",
        columns.max(1)
    );
    for c in charts {
        h.push_str("<div>");
        h.push_str(&svg_or_note(c));
        h.push_str("</div>");
    }
    h.push_str(&format!(
        "</div><figcaption>{caption}</figcaption></figure>"
    ));
    h
}

/// A table: header cells (a leading `<` marks a left-aligned column) and rows.
pub fn table(header: &[&str], rows: &[Vec<String>]) -> String {
    let left: Vec<bool> = header.iter().map(|h| h.starts_with('<')).collect();
    let cell = |tag: &str, i: usize, s: &str| {
        let cls = if left.get(i).copied().unwrap_or(false) {
            " class=\"l\""
        } else {
            ""
        };
        format!("<{tag}{cls}>{s}</{tag}>")
    };
    let mut h = String::from("<table><tr>");
    for (i, t) in header.iter().enumerate() {
        h.push_str(&cell("th", i, t.trim_start_matches('<')));
    }
    h.push_str("</tr>");
    for r in rows {
        h.push_str("<tr>");
        for (i, s) in r.iter().enumerate() {
            h.push_str(&cell("td", i, s));
        }
        h.push_str("</tr>");
    }
    h.push_str("</table>");
    h
}

/// The whole document around the sections' HTML.
pub fn document(title: &str, body: &str) -> String {
    format!(
        "<!doctype html><html lang=\"en\"><head><meta charset=\"utf-8\">\
         <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\
         <title>{}</title><style>{STYLE}</style></head><body>{body}</body></html>\n",
        escape(title)
    )
}
