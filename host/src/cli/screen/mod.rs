//! The screens the concluding commands print: the answer first (the
//! verdict's laws, the error before and after, how sure, the rivals, the
//! next step), wrapped at the terminal's width, the paper's symbols in
//! place of their ASCII spellings. The numbers are [`headline::Headline`]'s,
//! which the JSON carries too; everything else is behind `--verbose`.

pub use crate::format::rounding;
pub use crate::workbench::headline;
pub mod render;
pub mod study;
pub mod symbols;

/// Off a terminal (a pipe, a file, a test) lines stop at this many columns.
pub const PIPE_WIDTH: usize = 100;

/// The width to wrap stdout at: the terminal's, else [`PIPE_WIDTH`]; never
/// under 40 (a narrower window wraps every word).
pub fn width() -> usize {
    let term = console::Term::stdout();
    let w = match term.is_term() {
        true => term.size_checked().map_or(PIPE_WIDTH, |(_, c)| c as usize),
        false => PIPE_WIDTH,
    };
    w.max(40)
}

/// `text` wrapped at `width` columns, its first line after `first`, the
/// rest after `rest` (a hanging indent).
pub fn wrap(text: &str, width: usize, first: &str, rest: &str) -> String {
    let o = textwrap::Options::new(width)
        .initial_indent(first)
        .subsequent_indent(rest);
    textwrap::fill(text, o)
}

#[cfg(test)]
mod tests {
    use super::wrap;

    #[test]
    fn wrapped_lines_stay_within_the_width_and_hang_under_the_first() {
        let text = "the body's axial rotational resistance E_x rising with ψ = atan(2 π B_o/λ), \
                    and a second clause long enough to wrap twice at forty columns";
        let w = wrap(text, 40, "  1. ", "     ");
        for line in w.lines() {
            assert!(textwrap::core::display_width(line) <= 40, "{line:?}");
        }
        assert!(w.starts_with("  1. the body's"));
        assert!(w.lines().skip(1).all(|l| l.starts_with("     ")));
    }
}
