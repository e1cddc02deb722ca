//! Prints the base and the paper models' errors on the paper's data, and
//! checks that the paper's calibrated model is the better of the two on the
//! tails it was calibrated on (`B_o / R_body = 0.45`).
use swimbot::model::preset;
use swimbot::workbench::compare::compare;

fn main() {
    let data = swimbot::data::paper();
    for name in ["base", "paper", "paper-lighthill"] {
        let model = preset(name).expect("preset exists");
        let c = compare(&model, &data, 0).expect("paper data predicts");
        println!(
            "{name}: MARE {:.3}, chi2_red {:?}",
            c.summary.mare, c.summary.chi2_reduced
        );
        for k in &c.cases {
            println!(
                "  {:7} U {:.4} vs {:.4} ({:+.1} %)   Om {:.4} vs {:.4} ({:+.1} %)",
                k.id,
                k.u().pred,
                k.u().obs.unwrap(),
                100.0 * k.u().rel_err.unwrap(),
                k.omega().pred,
                k.omega().obs.unwrap(),
                100.0 * k.omega().rel_err.unwrap()
            );
        }
    }
}
