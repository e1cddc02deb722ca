//! Study: how far the linearised input-uncertainty bands can be trusted.
//! For the paper data and the paper's model, every tail input (wavelength,
//! amplitude, tail length) is given the same relative standard uncertainty
//! `r`, from 0.5 % to 20 %; the table shows the Monte-Carlo spread (2000
//! seeded draws) over the linear band for U and Omega_b, worst case over
//! the six tails. Asserts that at 1 % the two agree to 5 % and that the
//! ratio departs from 1 as `r` grows (the model is non-linear in `B_o`).
//! Run: `cargo run --release -p swimbot --example input_uncertainty`.

use swimbot::data::uncertainty::{field_id, Uncertainty};
use swimbot::model::preset;
use swimbot::workbench::propagate::{linear_band, monte_carlo};

fn main() {
    let model = preset("paper").expect("preset");
    let data = swimbot::data::paper();
    println!(
        "| r (each tail input) | worst MC/linear U | worst MC/linear Omega_b | mean U band / U |"
    );
    println!("|---|---|---|---|");
    let mut worst_at = Vec::new();
    for r in [0.5, 1.0, 2.0, 5.0, 10.0, 20.0] {
        let (mut wu, mut wo, mut rel) = (1.0f64, 1.0f64, 0.0);
        for case in &data.cases {
            let mut c = case.clone();
            c.inputs.uncertainties = ["wavelength_mm", "amplitude_mm", "tail_length_mm"]
                .iter()
                .map(|f| (field_id(f).unwrap(), Uncertainty::RelativePercent(r)))
                .collect();
            let band = linear_band(&model, &c).expect("band");
            let mc = monte_carlo(&model, &c, &band, 2000, 11).expect("monte carlo");
            let far = |a: f64, b: f64| {
                if (a - 1.0).abs() > (b - 1.0).abs() {
                    a
                } else {
                    b
                }
            };
            wu = far(mc.u_sd_ratio, wu);
            wo = far(mc.omega_sd_ratio, wo);
            rel += band.u_sd_mm_s / model.predict(&c).unwrap().u_mm_s.abs() / 6.0;
        }
        println!("| {r} % | {wu:.3} | {wo:.3} | {:.1} % |", 100.0 * rel);
        worst_at.push((r, (wu - 1.0).abs().max((wo - 1.0).abs())));
    }
    let at = |r: f64| worst_at.iter().find(|w| w.0 == r).unwrap().1;
    assert!(
        at(1.0) < 0.05,
        "linear and Monte Carlo differ by {} at 1 %",
        at(1.0)
    );
    assert!(at(20.0) > at(1.0), "no growth of the non-linearity with r");
    println!(
        "\nok: linear within 5 % at 1 %; departure grows to {:.0} % at 20 %",
        100.0 * at(20.0)
    );
}
