//! Checks of the non-local tail, body and wall models against classical
//! results: slender rods (Cox 1970, Batchelor 1970), the prolate spheroid
//! (Oberbeck / Chwang & Wu 1975), a sphere on a tube axis (Haberman & Sayre
//! 1958), convergence, reciprocity, positivity, mirror symmetry, and the
//! agreement of slender-body theory with regularized Stokeslets.
use nalgebra::Matrix6;
use std::f64::consts::PI;
use swimbot::nonlocal::curve::Centreline;
use swimbot::nonlocal::rigid::spd_check;
use swimbot::nonlocal::{
    free_body_resistance, mrs_line, robot_resistance, sbt, tail_resistance, NonlocalError,
    NonlocalSettings, TailMethod,
};
use swimbot::physics::geometry::{Body, Channel, Handedness, Helix};

const MU: f64 = 3.5;
/// Entries that set the swimming speed: axial drag, thrust coupling, axial torque.
const AXIAL: [(usize, usize); 3] = [(0, 0), (0, 3), (3, 3)];

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

fn settings(method: TailMethod, spt: usize) -> NonlocalSettings {
    NonlocalSettings::default()
        .with_method(method)
        .with_segments_per_turn(spt)
}

#[test]
fn straight_rod_drag_matches_cox_and_batchelor() {
    // Cox (1970) / Batchelor (1970), blunt cylinder of length l, radius a:
    // F_par = 2 pi mu l U / (ln(l/a) - 0.807), F_perp = 4 pi mu l U / (ln(l/a) + 0.193),
    // relative error O(1 / ln(l/a)^2) from the next term of the expansion.
    let mut prev_err = f64::INFINITY;
    for ratio in [1.0e3, 1.0e4] {
        let (len, a) = (1.0, 1.0 / ratio);
        let rod = Centreline::Rod {
            start_m: [0.0; 3],
            direction: [1.0, 0.0, 0.0],
            length_m: len,
        };
        let par = 2.0 * PI * MU * len / (f64::ln(ratio) - 0.807);
        let perp = 4.0 * PI * MU * len / (f64::ln(ratio) + 0.193);
        let bs = sbt::resistance(rod, a, MU, 80, false).unwrap();
        let bm = mrs_line::resistance(rod, a, MU, 40, mrs_line::MATCHED_BLOB_OVER_RADIUS, false)
            .unwrap();
        let errs = [
            rel(bs[(0, 0)], par),
            rel(bs[(1, 1)], perp),
            rel(bm[(0, 0)], par),
            rel(bm[(1, 1)], perp),
        ];
        println!(
            "l/a = {ratio:e}: SBT par/perp err {:.4} {:.4}, MRS {:.4} {:.4}",
            errs[0], errs[1], errs[2], errs[3]
        );
        let worst = errs.iter().cloned().fold(0.0, f64::max);
        // measured: 1.1 % at 1e3, 0.43 % at 1e4 (~ 1/ln^2 scaling)
        assert!(worst < 1.5 / f64::ln(ratio).powi(2), "worst error {worst}");
        assert!(worst < prev_err);
        prev_err = worst;
        // isotropy across the axis
        assert!(rel(bm[(2, 2)], bm[(1, 1)]) < 1e-9);
    }
}

#[test]
fn helix_mrs_converges_with_resolution() {
    // Tails #1 (longest) and #5 (most coiled). Reference: 48 segments per turn.
    for &k in &[0usize, 4] {
        let (l, b, lt) = swimbot::data::paper_tails_mm()[k];
        let h = Helix::from_mm(l, b, lt, 1.0);
        let fine =
            tail_resistance(&h, MU, &settings(TailMethod::RegularizedStokeslets, 48)).unwrap();
        println!(
            "tail #{}: spt  B_xx  B_x,wx  B_wx,wx  (relative to spt=48)",
            k + 1
        );
        for spt in [6usize, 8, 12, 16, 24] {
            let t0 = std::time::Instant::now();
            let bm =
                tail_resistance(&h, MU, &settings(TailMethod::RegularizedStokeslets, spt)).unwrap();
            let e: Vec<f64> = AXIAL
                .iter()
                .map(|&(i, j)| rel(bm[(i, j)], fine[(i, j)]))
                .collect();
            println!(
                "  {spt:3}  {:.2e}  {:.2e}  {:.2e}   ({:.0} ms)",
                e[0],
                e[1],
                e[2],
                t0.elapsed().as_secs_f64() * 1e3
            );
            if spt >= 12 {
                assert!(e.iter().all(|&x| x < 0.01), "spt {spt}: {e:?}");
            }
        }
    }
}

#[test]
fn helix_sbt_is_stable_over_its_admissible_resolutions() {
    let h = Helix::from_mm(15.5, 2.5, 130.0, 1.0);
    // segment 21.9/spt mm: spt 6..14 spans h = 7.3 a .. 3.1 a
    let bs: Vec<Matrix6<f64>> = [6usize, 10, 14]
        .iter()
        .map(|&s| tail_resistance(&h, MU, &settings(TailMethod::SlenderBody, s)).unwrap())
        .collect();
    for &(i, j) in &AXIAL {
        let spread = rel(bs[0][(i, j)], bs[2][(i, j)]).max(rel(bs[1][(i, j)], bs[2][(i, j)]));
        println!("SBT ({i},{j}): spread {spread:.4}");
        assert!(spread < 0.03, "({i},{j}) spread {spread}");
    }
}

#[test]
fn resistance_is_symmetric_positive_definite_for_all_paper_tails() {
    for (k, (l, b, lt)) in swimbot::data::paper_tails_mm().into_iter().enumerate() {
        let h = Helix::from_mm(l, b, lt, 1.0);
        for m in [TailMethod::SlenderBody, TailMethod::RegularizedStokeslets] {
            let bm = tail_resistance(&h, MU, &settings(m, 12)).unwrap();
            let (min_eig, asym) = spd_check(&bm);
            println!(
                "tail #{} {m:?}: min eig {min_eig:.3e}, asymmetry {asym:.2e}",
                k + 1
            );
            assert!(min_eig > 0.0);
            // MRS reciprocity is exact only for a symmetric quadrature; SBT collocation is not.
            assert!(asym < 0.02, "tail #{} {m:?} asymmetry {asym}", k + 1);
        }
    }
}

#[test]
fn sbt_and_regularized_stokeslets_agree_in_the_slender_limit() {
    // two turns of a lambda = 10 mm, B = 2.5 mm helix; wire thinner and thinner
    let mut prev = f64::INFINITY;
    for d_mm in [1.0, 0.1, 0.01] {
        let h = Helix::from_mm(10.0, 2.5, 20.0, d_mm);
        let s = settings(TailMethod::SlenderBody, 24);
        let bs = tail_resistance(&h, MU, &s).unwrap();
        let bm =
            tail_resistance(&h, MU, &s.with_method(TailMethod::RegularizedStokeslets)).unwrap();
        let worst = AXIAL
            .iter()
            .map(|&(i, j)| rel(bs[(i, j)], bm[(i, j)]))
            .fold(0.0, f64::max);
        println!("wire {d_mm} mm: worst axial SBT-vs-MRS difference {worst:.4}");
        assert!(worst < prev);
        prev = worst;
    }
    assert!(prev < 0.005, "{prev}");
}

#[test]
fn mirror_image_flips_the_thrust_coupling() {
    let right = Helix::from_mm(12.0, 4.5, 60.0, 1.0);
    let left = Helix {
        handedness: Handedness::Left,
        ..right
    };
    for m in [TailMethod::SlenderBody, TailMethod::RegularizedStokeslets] {
        let br = tail_resistance(&right, MU, &settings(m, 12)).unwrap();
        let bl = tail_resistance(&left, MU, &settings(m, 12)).unwrap();
        assert!(
            br[(0, 3)] < 0.0,
            "right-handed tail rotated about +x pushes towards -x?"
        );
        assert!(
            rel(-bl[(0, 3)], br[(0, 3)]) < 1e-9,
            "{} vs {}",
            bl[(0, 3)],
            br[(0, 3)]
        );
        assert!(rel(bl[(0, 0)], br[(0, 0)]) < 1e-9 && rel(bl[(3, 3)], br[(3, 3)]) < 1e-9);
    }
}

#[test]
fn bad_geometry_is_an_error_not_a_panic() {
    let s = NonlocalSettings::default();
    let ok = Helix::from_mm(10.0, 2.5, 88.0, 1.0);
    let cases = [
        Helix {
            axial_length_m: -1.0,
            ..ok
        },
        Helix {
            wavelength_m: 0.0,
            ..ok
        },
        Helix {
            wire_diameter_m: f64::NAN,
            ..ok
        },
        Helix {
            wire_diameter_m: 8e-3,
            ..ok
        }, // thicker than the gap between turns
        Helix {
            amplitude_m: -1e-3,
            ..ok
        },
    ];
    for h in cases {
        assert!(
            matches!(tail_resistance(&h, MU, &s), Err(NonlocalError::Geometry(_))),
            "{h:?}"
        );
    }
    assert!(matches!(
        tail_resistance(&ok, 0.0, &s),
        Err(NonlocalError::Settings(_))
    ));
    let s_bad = NonlocalSettings {
        segments_per_turn: 1,
        ..s
    };
    assert!(matches!(
        tail_resistance(&ok, MU, &s_bad),
        Err(NonlocalError::Settings(_))
    ));
    // tail joint inside the body
    let body = Body::from_mm(50.0, 20.0);
    assert!(matches!(
        robot_resistance(&body, &ok, MU, &s),
        Err(NonlocalError::Geometry(_))
    ));
    // robot wider than the channel
    let narrow = Channel {
        diameter_m: 0.015,
        length_m: 1.0,
        closed: true,
        vertical: true,
    };
    let behind = Helix {
        joint_x_m: -0.03,
        ..ok
    };
    assert!(matches!(
        swimbot::nonlocal::tube::robot_resistance_in_tube(
            &body,
            &behind,
            &narrow,
            MU,
            &swimbot::nonlocal::tube::TubeSettings::default()
        ),
        Err(NonlocalError::Geometry(_))
    ));
}

#[test]
fn prolate_spheroid_surface_matches_exact_drag() {
    // Chwang & Wu (1975) exact drags of a prolate spheroid, semi-axes c > b.
    let (c, b) = (2.5f64, 1.0f64);
    let e = (1.0 - b * b / (c * c)).sqrt();
    let le = ((1.0 + e) / (1.0 - e)).ln();
    let fx = 16.0 * PI * MU * c * e.powi(3) / ((1.0 + e * e) * le - 2.0 * e);
    let fy = 32.0 * PI * MU * c * e.powi(3) / (2.0 * e + (3.0 * e * e - 1.0) * le);
    let mut errs = vec![];
    for h in [0.3, 0.2] {
        let s = NonlocalSettings {
            body_spacing_m: h,
            ..Default::default()
        };
        let bb = free_body_resistance(
            &Body {
                length_m: 2.0 * c,
                diameter_m: 2.0 * b,
            },
            MU,
            &s,
        )
        .unwrap();
        let e = (rel(bb[(0, 0)], fx), rel(bb[(1, 1)], fy));
        println!(
            "spheroid h = {h}: axial err {:.4}, transverse err {:.4}",
            e.0, e.1
        );
        errs.push(e.0.max(e.1));
    }
    // O(eps) regularization error, halving with the spacing; 1.4 % measured at h = 0.15
    assert!(errs[1] < errs[0] && errs[1] < 0.04, "{errs:?}");
}
