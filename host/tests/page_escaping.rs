//! User text on the page, through the real binary: a dataset whose name
//! and case names, and a user effect whose statement, reference and
//! parameter doc hold markup (`<script>`, `<b>`), `&`, `"` and `'` are
//! shown as that text on the story page and on the study page, never as
//! markup; the bundle's tables hold the text itself, not its entities.
//! An effect's name cannot carry markup: it must be kebab-case, and a
//! file whose name is not is refused before anything is written.

use crate::common::run_in;
use crate::common::stderr;
use std::path::Path;

/// Appended to every case name.
const CASE_TAIL: &str = "<script>alert(1)</script>&\"q\"'s";
/// What the page shows for [`CASE_TAIL`]: escaped text.
const CASE_TAIL_ESCAPED: &str = "&lt;script&gt;alert(1)&lt;/script&gt;&amp;&quot;q&quot;'s";

const EFFECT: &str = r#"[[effect]]
name = "lab-drag"
statement = "the <b>body</b> & \"its\" wake's <script>alert(3)</script> drag"
reference = "a <i>lab</i> note & \"memo\""
applies_to = "all cases"

[[effect.param]]
name = "k"
unit = "1"
default = 1.0
min = 0.2
max = 10.0
doc = "a factor <script>alert(4)</script>"

[effect.places]
"body.D_x" = "k"
"#;

fn ok(cwd: &Path, args: &[&str]) {
    let o = run_in(cwd, args);
    assert!(o.status.success(), "{args:?}: {}", stderr(&o));
}

/// The paper's CSV with markup in the dataset's name and every case name,
/// and the user effect, in a fresh directory.
fn hostile_lab() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    let paper =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/data/paper.csv")).unwrap();
    let csv: String = paper
        .lines()
        .map(|l| {
            if l.starts_with("# name = ") {
                r#"# name = "lab <script>alert(2)</script> & \"quoted\" 'single'""#.to_string()
            } else if let Some((id, rest)) = l.split_once(',').filter(|_| l.starts_with("tail-")) {
                // a CSV field holding `"` is quoted, its quotes doubled
                format!("\"{id}{}\",{rest}", CASE_TAIL.replace('"', "\"\""))
            } else {
                l.to_string()
            }
        })
        .map(|l| l + "\n")
        .collect();
    std::fs::write(dir.path().join("lab.csv"), csv).unwrap();
    std::fs::write(dir.path().join("effect.toml"), EFFECT).unwrap();
    dir
}

/// No piece of the user's text reaches `page` as markup or unescaped,
/// and the case names are on it as escaped text.
fn assert_escaped(page: &str) {
    assert!(
        !page.to_ascii_lowercase().contains("<script"),
        "a <script> element on the page"
    );
    for raw in [
        "<b>body",
        "<i>lab",
        "&\"q\"",
        "\"its\"",
        "\"memo\"",
        "\"quoted\"",
        "& \"",
    ] {
        assert!(!page.contains(raw), "{raw} unescaped on the page");
    }
    assert!(
        page.contains(&format!("tail-1{CASE_TAIL_ESCAPED}")),
        "the case names are shown"
    );
}

/// The table CSVs of a bundle hold the case names as text.
fn assert_tables_hold_the_text(bundle: &Path) {
    let tables: Vec<String> = std::fs::read_dir(bundle.join("tables"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "csv"))
        .map(|p| std::fs::read_to_string(p).unwrap())
        .collect();
    let quoted = format!("\"tail-1{}\"", CASE_TAIL.replace('"', "\"\""));
    assert!(
        tables.iter().any(|t| t.contains(&quoted)),
        "no table holds the case name {quoted}"
    );
    assert!(tables.iter().all(|t| !t.contains("&lt;")));
}

#[test]
fn user_text_on_the_story_page_is_text() {
    let dir = hostile_lab();
    let d = dir.path();
    ok(
        d,
        &[
            "compare",
            "--quiet",
            "--data",
            "lab.csv",
            "--effect-file",
            "effect.toml",
            "--effect",
            "lab-drag",
            "-o",
            "out",
        ],
    );
    let page = std::fs::read_to_string(d.join("out/index.html")).unwrap();
    assert_escaped(&page);
    assert!(page.contains("lab &lt;script&gt;alert(2)&lt;/script&gt; &amp; &quot;quoted&quot;"));
    assert_tables_hold_the_text(&d.join("out"));
}

#[test]
fn user_text_on_the_study_page_is_text() {
    let dir = hostile_lab();
    let d = dir.path();
    ok(d, &["init", "--quiet", "--data", "lab.csv"]);
    ok(d, &["add", "--quiet", "--force", "effect.toml"]);
    ok(d, &["report", "--quiet"]);
    let bundle = d.join("swimbot-out/report");
    let page = std::fs::read_to_string(bundle.join("index.html")).unwrap();
    assert_escaped(&page);
    // the effect's statement and reference, as text
    assert!(page.contains(
        "the &lt;b&gt;body&lt;/b&gt; &amp; &quot;its&quot; wake's \
         &lt;script&gt;alert(3)&lt;/script&gt; drag"
    ));
    assert!(page.contains("a &lt;i&gt;lab&lt;/i&gt; note &amp; &quot;memo&quot;"));
    assert_tables_hold_the_text(&bundle);
}

#[test]
fn an_effect_named_with_markup_is_refused() {
    let dir = hostile_lab();
    let d = dir.path();
    let named = EFFECT.replace("\"lab-drag\"", "\"drag<script>x</script>\"");
    std::fs::write(d.join("named.toml"), named).unwrap();
    let o = run_in(
        d,
        &[
            "compare",
            "--data",
            "lab.csv",
            "--effect-file",
            "named.toml",
            "-o",
            "out",
        ],
    );
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("kebab-case"), "{}", stderr(&o));
    assert!(!d.join("out").exists());
}
