//! The page's frame: one self-contained HTML document (inline CSS and SVG,
//! no external resource), readable on a laptop screen and printable
//! (figures and tables never split across pages), and the small HTML
//! helpers the sections share. Every piece of the page is [`Markup`] built
//! with maud's `html!`, which escapes all text it is given; the only raw
//! markup taken in is the charts' SVG and the constant stylesheet (each
//! marked where it enters), so a case name, an effect's statement or a
//! file path can never become markup on the page. Tables and figures are
//! [`Part`]s: their markup with what the bundle makes files of
//! ([`super::page`]).

use super::page::{Page, Part};
use maud::PreEscaped;
use maud::DOCTYPE;
pub use maud::{html, Markup, Render};

/// A chart's SVG, or why it could not be drawn.
pub type Chart = crate::chart::PlotResult;

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
.answer{background:#f4f8fb;border-left:4px solid #3b82c4;padding:.1em 1em .5em;margin:.8em 0}\
.answer h2{margin-top:.4em;border:0}.answer p,.answer ul{margin:.35em 0}.answer table{background:#fff}\
.answer td.params{white-space:normal;max-width:34em}.answer td.l{max-width:34em}\
@media (max-width:900px){.grid{grid-template-columns:repeat(2,minmax(0,max-content))}\
.flow .grid{grid-template-rows:repeat(var(--rows),auto);grid-auto-flow:column}}\
@media print{body{max-width:none;margin:0;padding:0;font-size:10pt}h2{break-after:avoid;page-break-after:avoid}\
table,figure,.verdict{break-inside:avoid;page-break-inside:avoid}.toc{display:none}\
.grid{grid-template-columns:repeat(2,minmax(0,max-content))}.flow .grid{grid-template-rows:repeat(var(--rows),auto);grid-auto-flow:column}\
@page{size:A4;margin:14mm}}";

/// The stylesheet as markup. Trusted raw markup: a constant of this file,
/// with no input in it.
fn style() -> Markup {
    PreEscaped(STYLE.to_string())
}

/// Text in physics notation as HTML: escaped, `Omega_b` as Ω<sub>b</sub>,
/// `x^2` as x<sup>2</sup> (the same runs the charts draw).
pub fn rich(s: &str) -> Markup {
    let runs = crate::chart::notation_runs(&crate::chart::notation(s));
    html! {
        @for (t, shift) in runs {
            @match shift {
                0 => (t),
                -1 => sub { (t) },
                _ => sup { (t) },
            }
        }
    }
}

/// Ω<sub>b</sub>, the body's rate, as the page writes it.
pub fn omega_b() -> Markup {
    html! { "Ω" sub { "b" } }
}

/// A chart, or a visible note where it failed.
pub fn svg_or_note(r: &Chart) -> Markup {
    match r {
        // Trusted raw markup: SVG from the chart engine (`crate::chart`) or
        // the path chart, which escape every text they draw
        // (`crate::chart::escape_text`) and put no text in attributes.
        Ok(svg) => PreEscaped(svg.clone()),
        Err(e) => html! { p.err { "chart failed: " (e) } },
    }
}

/// A figure of charts in a grid of `columns`, with its caption: its
/// panels are files of the bundle.
pub fn figure(id: &str, charts: &[Chart], columns: usize, caption: Markup) -> Part {
    figure_in(id, None, None, charts, columns, caption)
}

/// [`figure`] for panels given row by row that, on paper and on narrow
/// screens (two columns), are laid out column by column instead, so that
/// each printed row keeps one column of the wide layout together (Fig. 4:
/// each group's U beside its Omega_b).
/// `legend`, one for every panel, is drawn above the grid so that no panel
/// is widened by it.
pub fn figure_flow(
    id: &str,
    legend: Option<&Chart>,
    charts: &[Chart],
    columns: usize,
    caption: Markup,
) -> Part {
    let rows = charts.len().div_ceil(2).max(1);
    let flow = (columns == rows).then_some(rows);
    figure_in(id, flow, legend, charts, columns, caption)
}

fn figure_in(
    id: &str,
    flow_rows: Option<usize>,
    legend: Option<&Chart>,
    charts: &[Chart],
    columns: usize,
    caption: Markup,
) -> Part {
    let caption = caption.into_string();
    let drawn = |c: &Chart| c.as_ref().ok().cloned();
    // Each SVG is shown at its own size (its ticks read at the size they
    // were drawn), shrunk only when the columns do not fit.
    let markup = html! {
        figure id=(id) class=[flow_rows.map(|_| "flow")]
            style=[flow_rows.map(|r| format!("--rows:{r}"))] {
            @if let Some(l) = legend {
                div.fig-legend { (svg_or_note(l)) }
            }
            div.grid style={ "--cols:" (columns.max(1)) } {
                @for c in charts {
                    div { (svg_or_note(c)) }
                }
            }
            // markup built by `html!` above, put back as it was
            figcaption { (PreEscaped(&caption)) }
        }
    };
    let legend = legend.and_then(drawn);
    Part::figure(
        markup,
        id,
        &caption,
        legend,
        charts.iter().filter_map(drawn).collect(),
    )
}

/// A table's header cell: its content and whether its column is
/// left-aligned (text) rather than right-aligned (numbers).
#[derive(Clone)]
pub struct Head {
    content: Markup,
    left: bool,
}

impl Head {
    /// A right-aligned column headed by `content`.
    pub fn num(content: Markup) -> Head {
        Head {
            content,
            left: false,
        }
    }

    /// A left-aligned column headed by `content`.
    pub fn text(content: Markup) -> Head {
        Head {
            content,
            left: true,
        }
    }
}

/// Plain header text (the page's own words: a header holding a user's
/// text is built with [`Head::num`] or [`Head::text`]); a leading `<`
/// marks a left-aligned column.
impl From<&str> for Head {
    fn from(s: &str) -> Head {
        match s.strip_prefix('<') {
            Some(t) => Head::text(t.render()),
            None => Head::num(s.render()),
        }
    }
}

impl From<String> for Head {
    fn from(s: String) -> Head {
        Head::from(s.as_str())
    }
}

/// A table: header cells and rows of cells (text is escaped, markup
/// kept); a file of the bundle as CSV and JSON.
pub fn table<H, C>(header: &[H], rows: &[Vec<C>]) -> Part
where
    H: Clone + Into<Head>,
    C: Render,
{
    let header: Vec<Head> = header.iter().cloned().map(Into::into).collect();
    let left = |i: usize| header.get(i).is_some_and(|h| h.left).then_some("l");
    let mut cells = vec![header
        .iter()
        .map(|h| h.content.clone().into_string())
        .collect::<Vec<_>>()];
    cells.extend(
        rows.iter()
            .map(|r| r.iter().map(|c| c.render().into_string()).collect()),
    );
    // every cell is markup built by `html!` (its `Render`), put back as it was
    let markup = html! {
        table {
            tr {
                @for (i, h) in cells[0].iter().enumerate() {
                    th class=[left(i)] { (PreEscaped(h)) }
                }
            }
            @for r in &cells[1..] {
                tr {
                    @for (i, c) in r.iter().enumerate() {
                        td class=[left(i)] { (PreEscaped(c)) }
                    }
                }
            }
        }
    };
    Part::table(markup, &cells)
}

/// A cell of [`classed_table`]: its class (`l params`, or none) and content.
pub type Cell = (Option<&'static str>, Markup);

/// A table of class `class` whose rows (header first, as `th`) give each
/// cell its own class; a file of the bundle as CSV and JSON as [`table`].
pub fn classed_table(class: &str, rows: &[Vec<Cell>]) -> Part {
    let markup = html! {
        table class=(class) {
            @for (i, r) in rows.iter().enumerate() {
                tr {
                    @for (c, m) in r {
                        @if i == 0 {
                            th class=[*c] { (m) }
                        } @else {
                            td class=[*c] { (m) }
                        }
                    }
                }
            }
        }
    };
    let cells: Vec<Vec<String>> = rows
        .iter()
        .map(|r| r.iter().map(|(_, m)| m.clone().into_string()).collect())
        .collect();
    Part::table(markup, &cells)
}

/// The whole document around the sections, with its artefacts.
pub fn document(title: &str, body: Part) -> Page {
    let page = html! {
        (DOCTYPE)
        html lang="en" {
            head {
                meta charset="utf-8";
                meta name="viewport" content="width=device-width, initial-scale=1";
                title { (title) }
                style { (style()) }
            }
            // the sections' markup, built by `html!`
            body { (PreEscaped(body.html())) }
        }
    };
    Page::new(page.into_string() + "\n", body)
}
