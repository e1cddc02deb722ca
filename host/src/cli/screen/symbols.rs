//! The paper's symbols in print: `Omega_b` as Ω_b, `N_lambda` as N_λ,
//! `psi` as ψ, `B_t[wx,wx]` as B_t[ωx,ωx], `*` as ·, so that the screens
//! and tables read as the paper does (its nomenclature, sec. 2).

/// `s` with the paper's ASCII spellings replaced by their symbols; words
/// are matched whole (`pitch` keeps its `pi`).
pub fn symbols(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    let mut word = String::new();
    let flush = |word: &mut String, out: &mut String| {
        out.push_str(match word.as_str() {
            "Omega_b" => "Ω_b",
            "Omega" => "Ω",
            "N_lambda" => "N_λ",
            "lambda" => "λ",
            "omega" => "ω",
            "psi" => "ψ",
            "pi" => "π",
            "wx" => "ωx",
            "chi2" => "χ²",
            "chi2_red" => "χ²/ν",
            w => w,
        });
        word.clear();
    };
    for ch in s.chars() {
        if ch.is_alphanumeric() || ch == '_' {
            word.push(ch);
        } else {
            flush(&mut word, &mut out);
            out.push(ch);
        }
    }
    flush(&mut word, &mut out);
    out.replace(" * ", " · ")
}

#[cfg(test)]
mod tests {
    use super::symbols;

    #[test]
    fn whole_words_become_symbols_and_others_stay() {
        assert_eq!(
            symbols("psi = atan(2 pi B_o/lambda)"),
            "ψ = atan(2 π B_o/λ)"
        );
        assert_eq!(
            symbols("tau_t = B_t[wx,x] U + B_t[wx,wx] omega"),
            "tau_t = B_t[ωx,x] U + B_t[ωx,ωx] ω"
        );
        assert_eq!(
            symbols("Omega_b vs pitch_angle_deg"),
            "Ω_b vs pitch_angle_deg"
        );
        assert_eq!(symbols("k * x^p"), "k · x^p");
    }
}
