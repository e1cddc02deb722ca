//! What a page builds, as data: its HTML and, beside it, its artefacts,
//! the files of its bundle (each figure panel's SVG, the figure's legend,
//! each table as CSV and JSON, the study's paper-ready tables). The
//! sections build [`Part`]s, markup with the headings, tables and figures
//! in it recorded in page order; [`Page::new`] names the files from them
//! (a figure's files by its id, a table's by the section it stands in and
//! its place there), so the bundle ([`super::bundle`]) writes a list and
//! never reads the page back.

use super::html::Markup;
use maud::PreEscaped;

/// One file of the bundle: where it goes, what it is, and its text.
#[derive(Debug, Clone, PartialEq)]
pub struct Artefact {
    /// Relative to the folder (`figures/NAME`, `tables/NAME`).
    pub file: String,
    /// `figure` (SVG), `table-csv`, `table-json`, `table-latex`,
    /// `table-markdown`, `equations-latex`, `equations-markdown`.
    pub kind: &'static str,
    pub caption: String,
    pub text: String,
}

/// What a piece of the page holds that the bundle names or writes.
#[derive(Debug, Clone)]
enum Item {
    /// A section's heading: its tables are named by its id.
    Heading { id: String, title: String },
    /// A table's rows of cell texts, header first.
    Table { rows: Vec<Vec<String>> },
    /// A figure: its id, its caption's text, its one legend and its panels
    /// (the SVGs drawn; a chart that failed shows a note and is no file).
    Figure {
        id: String,
        caption: String,
        legend: Option<String>,
        panels: Vec<String>,
    },
}

/// A piece of a page: its markup, and the headings, tables and figures in
/// it in the order the markup holds them.
#[derive(Debug, Default)]
#[must_use = "a part's tables and figures are lost unless it is pushed into the page"]
pub struct Part {
    html: String,
    items: Vec<Item>,
}

impl From<Markup> for Part {
    fn from(m: Markup) -> Part {
        Part {
            html: m.into_string(),
            items: Vec::new(),
        }
    }
}

impl Part {
    pub fn new() -> Part {
        Part::default()
    }

    /// `p` after what is already here.
    pub fn push(&mut self, p: impl Into<Part>) {
        let p = p.into();
        self.html.push_str(&p.html);
        self.items.extend(p.items);
    }

    /// [`Part::push`], returning the part.
    pub fn with(mut self, p: impl Into<Part>) -> Part {
        self.push(p);
        self
    }

    /// The part inside the markup `around` builds of it (a `<section>`, a
    /// `<div>`): `around` adds no table or figure of its own.
    pub fn wrap(self, around: impl FnOnce(Markup) -> Markup) -> Part {
        Part {
            html: around(PreEscaped(self.html)).into_string(),
            items: self.items,
        }
    }

    /// The markup of a section's heading with its `id`.
    pub fn heading(id: &str, markup: Markup) -> Part {
        let html = markup.into_string();
        Part {
            items: vec![Item::Heading {
                id: id.to_string(),
                title: text_of(&html),
            }],
            html,
        }
    }

    /// The markup of a table whose cells (header first) are `cells`
    /// rendered, each cell's text becoming a field of its CSV and JSON.
    pub fn table(markup: Markup, cells: &[Vec<String>]) -> Part {
        let rows = cells
            .iter()
            .map(|r| r.iter().map(|c| text_of(c)).collect())
            .collect();
        Part {
            html: markup.into_string(),
            items: vec![Item::Table { rows }],
        }
    }

    /// The markup of figure `id` with its `caption` (rendered), its
    /// `legend` and `panels` as drawn.
    pub fn figure(
        markup: Markup,
        id: &str,
        caption: &str,
        legend: Option<String>,
        panels: Vec<String>,
    ) -> Part {
        Part {
            html: markup.into_string(),
            items: vec![Item::Figure {
                id: id.to_string(),
                caption: text_of(caption),
                legend,
                panels,
            }],
        }
    }

    /// The markup so far.
    pub fn html(&self) -> &str {
        &self.html
    }
}

/// A page as built: its HTML and its artefacts, figures first, then
/// tables, each in page order, then what the page's maker adds.
#[derive(Debug)]
pub struct Page {
    pub html: String,
    pub artefacts: Vec<Artefact>,
}

impl Page {
    /// The page `html` whose body `body` was, its artefacts named.
    pub fn new(html: String, body: Part) -> Page {
        let items = body.items;
        let mut artefacts = Vec::new();
        for item in &items {
            if let Item::Figure {
                id,
                caption,
                legend,
                panels,
            } = item
            {
                figure_files(&mut artefacts, id, caption, legend.as_deref(), panels);
            }
        }
        table_files(&mut artefacts, &items);
        Page { html, artefacts }
    }
}

/// A figure's files: its one legend, drawn beside its panels, is a file of
/// its own and not a numbered panel; a figure of one panel is `ID.svg`.
fn figure_files(
    out: &mut Vec<Artefact>,
    id: &str,
    caption: &str,
    legend: Option<&str>,
    panels: &[String],
) {
    if let Some(svg) = legend {
        out.push(Artefact {
            file: format!("figures/{id}-legend.svg"),
            kind: "figure",
            caption: format!("legend of every panel. {caption}"),
            text: svg_file(svg),
        });
    }
    for (i, svg) in panels.iter().enumerate() {
        let file = if panels.len() == 1 {
            format!("figures/{id}.svg")
        } else {
            format!("figures/{id}-{}.svg", i + 1)
        };
        out.push(Artefact {
            file,
            kind: "figure",
            caption: format!(
                "{}: panel {} of {}. {caption}",
                svg_title(svg),
                i + 1,
                panels.len()
            ),
            text: svg_file(svg),
        });
    }
}

/// An SVG as its file holds it: the drawing, then one line end.
fn svg_file(svg: &str) -> String {
    format!("{}\n", svg.trim_end())
}

/// Every table as CSV and JSON, named by the section it stands in
/// (`page` before the first heading) and its place there.
fn table_files(out: &mut Vec<Artefact>, items: &[Item]) {
    let mut section = "page";
    let mut title = "";
    let mut count = std::collections::HashMap::<&str, usize>::new();
    for item in items {
        match item {
            Item::Heading { id, title: t } => {
                section = id;
                title = t;
            }
            Item::Table { rows } => {
                let n = count.entry(section).or_default();
                *n += 1;
                let stem = format!("tables/{section}-{n}");
                let csv: String = rows
                    .iter()
                    .map(|r| r.iter().map(|c| csv_field(c)).collect::<Vec<_>>().join(",") + "\n")
                    .collect();
                let caption = format!("table {n} of section \"{title}\"");
                out.push(Artefact {
                    file: format!("{stem}.csv"),
                    kind: "table-csv",
                    caption: caption.clone(),
                    text: csv,
                });
                out.push(Artefact {
                    file: format!("{stem}.json"),
                    kind: "table-json",
                    caption,
                    text: table_json(rows),
                });
            }
            Item::Figure { .. } => {}
        }
    }
}

/// The text of `html` with tags removed and the page's entities decoded.
pub fn text_of(html: &str) -> String {
    let mut out = String::with_capacity(html.len());
    let mut in_tag = false;
    let html = html.replace("<br>", " ");
    for ch in html.chars() {
        match ch {
            '<' => in_tag = true,
            '>' if in_tag => in_tag = false,
            c if !in_tag => out.push(c),
            _ => {}
        }
    }
    out.replace("&lt;", "<")
        .replace("&gt;", ">")
        .replace("&quot;", "\"")
        .replace("&#39;", "'")
        .replace("&amp;", "&")
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ")
}

fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// A panel's title: its text in the largest font (the first of those).
fn svg_title(svg: &str) -> String {
    let size = |t: &str| {
        attr(t, "font-size")
            .and_then(|s| s.parse::<f64>().ok())
            .unwrap_or(0.0)
    };
    let texts = elements(svg, "text");
    let best = texts.iter().fold(None::<&&str>, |b, t| match b {
        Some(b) if size(b) >= size(t) => Some(b),
        _ => Some(t),
    });
    best.map(|t| text_of(t)).unwrap_or_default()
}

/// The elements `<tag ...>...</tag>` of `svg` in order, without nesting.
fn elements<'a>(svg: &'a str, tag: &str) -> Vec<&'a str> {
    let (open, close) = (format!("<{tag}"), format!("</{tag}>"));
    let mut out = Vec::new();
    let mut rest = svg;
    while let Some(i) = rest.find(&open) {
        let Some(j) = rest[i..].find(&close) else {
            break;
        };
        out.push(&rest[i..i + j + close.len()]);
        rest = &rest[i + j + close.len()..];
    }
    out
}

fn attr<'a>(element: &'a str, name: &str) -> Option<&'a str> {
    let head = &element[..element.find('>')?];
    let key = format!("{name}=\"");
    let i = head.find(&key)? + key.len();
    Some(&head[i..i + head[i..].find('"')?])
}

/// A cell as JSON: a number when its text is one (a column of values
/// reads as numbers, not strings), else its text.
fn cell_json(text: &str) -> serde_json::Value {
    text.parse::<f64>()
        .ok()
        .filter(|v| v.is_finite())
        .and_then(serde_json::Number::from_f64)
        .map_or_else(
            || serde_json::Value::String(text.to_string()),
            serde_json::Value::Number,
        )
}

/// Rows as a JSON array of objects keyed by the header's texts.
fn table_json(rows: &[Vec<String>]) -> String {
    let Some((head, body)) = rows.split_first() else {
        return "[]".into();
    };
    let objects: Vec<serde_json::Map<String, serde_json::Value>> = body
        .iter()
        .map(|r| {
            head.iter()
                .zip(r)
                .map(|(k, v)| (k.clone(), cell_json(v)))
                .collect()
        })
        .collect();
    serde_json::to_string_pretty(&objects).expect("strings serialise") + "\n"
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use maud::html;

    /// A page of one section holding a table and a figure of two panels.
    pub(crate) fn sample() -> Part {
        let cells = vec![
            vec!["x, y".to_string(), "U (mm/s)".to_string()],
            vec![
                "tail-1".to_string(),
                "0.2609 &plusmn; 1<br><span class=\"fall\">falls</span>".to_string(),
            ],
        ];
        let panels = vec![
            "<svg><text font-size=\"11\">8.4</text><text font-size=\"14\">(a) first</text></svg>"
                .to_string(),
            "<svg><text>(b)</text></svg>".to_string(),
        ];
        Part::new()
            .with(Part::heading("a", html! { h2 id="a" { "1. One" } }))
            .with(Part::table(html! { table {} }, &cells))
            .with(Part::figure(
                html! { figure id="f" {} },
                "f",
                "<b>Fig.</b> Two &amp; panels.",
                None,
                panels,
            ))
    }

    #[test]
    fn every_panel_and_table_becomes_a_named_artefact() {
        let page = Page::new(String::new(), sample());
        let names: Vec<&str> = page.artefacts.iter().map(|a| a.file.as_str()).collect();
        assert_eq!(
            names,
            [
                "figures/f-1.svg",
                "figures/f-2.svg",
                "tables/a-1.csv",
                "tables/a-1.json"
            ]
        );
        let a = &page.artefacts;
        assert!(a[0]
            .caption
            .starts_with("(a) first: panel 1 of 2. Fig. Two & panels."));
        assert_eq!(
            a[2].text,
            "\"x, y\",U (mm/s)\ntail-1,0.2609 &plusmn; 1 falls\n"
        );
        let json: serde_json::Value = serde_json::from_str(&a[3].text).unwrap();
        assert_eq!(json[0]["U (mm/s)"], "0.2609 &plusmn; 1 falls");
        assert_eq!(a[2].caption, "table 1 of section \"1. One\"");
    }
}
