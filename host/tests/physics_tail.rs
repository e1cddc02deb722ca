//! Tail resistance (eq. 3): the closed forms against the paper's quadrature,
//! the quadrature's convergence order, and the matrix's physical properties.

use nalgebra::Matrix6;
use proptest::prelude::*;
use swimbot::physics::coefficients::CoefficientSet;
use swimbot::physics::geometry::Helix;
use swimbot::physics::tail::{
    axial_closed_form, matrix_exact, matrix_quadrature, quadrature_nodes,
    PAPER_NODES_PER_WAVELENGTH,
};

const MU: f64 = 3.5;

fn paper_tails() -> Vec<Helix> {
    swimbot::data::paper_tails_mm()
        .into_iter()
        .map(|(l, b, len)| Helix::from_mm(l, b, len, 1.0))
        .collect()
}

fn rel_diff(a: &Matrix6<f64>, b: &Matrix6<f64>) -> f64 {
    (a - b).norm() / b.norm()
}

#[test]
fn tail_one_uses_839_nodes_at_the_papers_resolution() {
    assert_eq!(
        quadrature_nodes(&paper_tails()[0], PAPER_NODES_PER_WAVELENGTH),
        839
    );
}

#[test]
fn exact_matrix_reproduces_the_closed_form_axial_entries() {
    for set in CoefficientSet::all() {
        for h in paper_tails() {
            let drag = set.local_drag(&h, MU).unwrap();
            let m = matrix_exact(&h, drag);
            let a = axial_closed_form(&h, drag);
            assert!((m[(0, 0)] / a.drag_n_s_per_m - 1.0).abs() < 1e-10);
            assert!((m[(0, 3)] / a.thrust_n_s - 1.0).abs() < 1e-10);
            assert!((m[(3, 3)] / a.torque_n_m_s - 1.0).abs() < 1e-10);
        }
    }
}

#[test]
fn quadrature_converges_to_the_exact_matrix_at_second_order() {
    for h in paper_tails() {
        let h = Helix {
            phase_rad: 0.4,
            joint_x_m: -0.03,
            ..h
        };
        let drag = CoefficientSet::GrayHancock.local_drag(&h, MU).unwrap();
        let exact = matrix_exact(&h, drag);
        let errors: Vec<f64> = [50, 100, 200, 400]
            .iter()
            .map(|&n| rel_diff(&matrix_quadrature(&h, drag, n), &exact))
            .collect();
        assert!(errors[1] < 1e-3, "paper resolution error {}", errors[1]);
        for w in errors.windows(2) {
            let order = (w[0] / w[1]).log2();
            assert!(
                (order - 2.0).abs() < 0.3,
                "observed order {order} from {errors:?}"
            );
        }
    }
}

#[test]
fn matrices_are_symmetric_positive_definite() {
    for h in paper_tails() {
        for set in CoefficientSet::all() {
            let drag = set.local_drag(&h, MU).unwrap();
            for m in [matrix_exact(&h, drag), matrix_quadrature(&h, drag, 100)] {
                assert!((m - m.transpose()).norm() <= 1e-14 * m.norm());
                assert!(m.cholesky().is_some(), "not positive definite: {m}");
            }
        }
    }
}

#[test]
fn mirror_image_flips_the_thrust_coupling_and_keeps_the_drags() {
    for h in paper_tails() {
        let drag = CoefficientSet::GrayHancock.local_drag(&h, MU).unwrap();
        let (r, l) = (matrix_exact(&h, drag), matrix_exact(&h.mirrored(), drag));
        assert!(r[(0, 3)] < 0.0, "right-handed helix must push along +x");
        assert!((r[(0, 3)] + l[(0, 3)]).abs() < 1e-12 * r[(0, 3)].abs());
        for i in 0..6 {
            assert!((r[(i, i)] - l[(i, i)]).abs() < 1e-12 * r[(i, i)].abs());
        }
    }
}

#[test]
fn whole_turns_make_the_lateral_force_coupling_vanish() {
    // Over an integer number of turns, the lateral forces of a rotating helix
    // cancel: the translation-rotation coupling has no y or z force from x-rotation.
    let h = Helix::from_mm(10.0, 2.5, 40.0, 1.0);
    let drag = CoefficientSet::GrayHancock.local_drag(&h, MU).unwrap();
    let m = matrix_exact(&h, drag);
    assert!(m[(1, 3)].abs() < 1e-12 * m[(0, 3)].abs());
    assert!(m[(2, 3)].abs() < 1e-12 * m[(0, 3)].abs());
    let half = Helix {
        axial_length_m: 0.045,
        ..h
    };
    let m = matrix_exact(&half, drag);
    assert!(m[(1, 3)].abs() + m[(2, 3)].abs() > 1e-3 * m[(0, 3)].abs());
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn exact_equals_fine_quadrature_for_any_geometry_and_phase(
        lambda_mm in 4.0f64..40.0,
        b_mm in 0.5f64..10.0,
        waves in 0.3f64..12.0,
        phase in 0.0f64..6.3,
        joint_mm in -80.0f64..0.0,
    ) {
        let h = Helix {
            phase_rad: phase,
            joint_x_m: joint_mm * 1e-3,
            ..Helix::from_mm(lambda_mm, b_mm, waves * lambda_mm, 1.0)
        };
        let drag = CoefficientSet::GrayHancock.local_drag(&h, 1.0).unwrap();
        let exact = matrix_exact(&h, drag);
        let fine = matrix_quadrature(&h, drag, 4000);
        prop_assert!(rel_diff(&fine, &exact) < 2e-6, "rel diff {}", rel_diff(&fine, &exact));
    }

    #[test]
    fn resistance_scales_linearly_with_viscosity(mu in 0.01f64..100.0) {
        let h = Helix::from_mm(12.0, 4.5, 60.0, 1.0);
        let m1 = matrix_exact(&h, CoefficientSet::Lighthill.local_drag(&h, 1.0).unwrap());
        let m = matrix_exact(&h, CoefficientSet::Lighthill.local_drag(&h, mu).unwrap());
        prop_assert!(rel_diff(&(m1 * mu), &m) < 1e-12);
    }
}
