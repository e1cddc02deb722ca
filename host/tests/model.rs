//! The swimmer model as physics: scaling laws, mirror symmetry, the signs
//! of the paper's additions, and the time-domain procedure against the
//! direct solve.

use swimbot::data::{self, Case};
use swimbot::effects::parse_effect_spec;
use swimbot::model::time_domain::{integrate, phase_average, TimeDomainSettings};
use swimbot::model::{preset, Model, TailMethod};
use swimbot::physics::geometry::Handedness;
use swimbot::physics::solve::Dofs;

fn cases() -> Vec<Case> {
    data::paper().cases
}

fn with(spec: &str) -> Model {
    Model::base().with_effect(parse_effect_spec(spec).unwrap())
}

#[test]
fn speed_is_proportional_to_frequency_and_ratios_ignore_viscosity() {
    let m = preset("paper").unwrap();
    let m_self = with("backflow").with_effect(parse_effect_spec("body-confinement").unwrap());
    for model in [Model::base(), m_self] {
        for c in cases() {
            let p = model.predict(&c).unwrap();
            let fast = Case {
                frequency_hz: 2.5 * c.frequency_hz,
                ..c.clone()
            };
            let q = model.predict(&fast).unwrap();
            assert!((q.u_mm_s / p.u_mm_s - 2.5).abs() < 1e-12);
            assert!((q.omega_body_hz / p.omega_body_hz - 2.5).abs() < 1e-12);
            let thick = Case {
                viscosity_pa_s: 12.5,
                ..c.clone()
            };
            let r = model.predict(&thick).unwrap();
            assert!((r.u_over_u_wave / p.u_over_u_wave - 1.0).abs() < 1e-12);
            assert!((r.omega_ratio / p.omega_ratio - 1.0).abs() < 1e-12);
        }
    }
    // The paper's observed-U back-flow is a fixed force: not proportional.
    let c = &cases()[2];
    let p = m.predict(c).unwrap();
    let q = m
        .predict(&Case {
            frequency_hz: 2.0 * c.frequency_hz,
            ..c.clone()
        })
        .unwrap();
    assert!((q.u_mm_s / p.u_mm_s - 2.0).abs() > 1e-3);
}

#[test]
fn the_base_model_swims_body_first_and_counter_rotates() {
    for c in cases() {
        let p = Model::base().predict(&c).unwrap();
        assert!(p.u_mm_s > 0.0 && p.omega_body_hz > 0.0, "{}: {p:?}", c.id);
        assert!(p.u_over_u_wave < 1.0, "a helix cannot outrun its wave");
    }
}

#[test]
fn a_left_handed_tail_swims_backwards_at_the_same_speed() {
    for c in cases() {
        let p = Model::base().predict(&c).unwrap();
        let left = Case {
            handedness: Handedness::Left,
            ..c.clone()
        };
        let q = Model::base().predict(&left).unwrap();
        assert!((q.u_mm_s + p.u_mm_s).abs() < 1e-12 * p.u_mm_s.abs());
        // Torque does not depend on handedness; counter-rotation keeps its sign.
        assert!((q.omega_body_hz - p.omega_body_hz).abs() < 1e-12 * p.omega_body_hz);
    }
}

#[test]
fn backflow_is_drag_in_both_variants() {
    for c in cases() {
        let base = Model::base().predict(&c).unwrap().u_mm_s;
        let selfc = with("backflow").predict(&c).unwrap().u_mm_s;
        let obs = with("backflow-observed").predict(&c).unwrap().u_mm_s;
        assert!(selfc < base && obs < base, "{}: {base} {selfc} {obs}", c.id);
        // With the observed U set to the self-consistent prediction, the two agree.
        let mut c2 = c.clone();
        c2.u_mm_s.as_mut().unwrap().mean = selfc;
        let again = with("backflow-observed").predict(&c2).unwrap().u_mm_s;
        assert!((again - selfc).abs() < 1e-12 * selfc);
    }
}

#[test]
fn body_correction_factors_scale_the_body_resistance() {
    let c = &cases()[0];
    let b0 = Model::base().body_matrix(c).unwrap();
    let b = with("body-correction:translation=16,rotation=1.4")
        .body_matrix(c)
        .unwrap();
    assert!((b[(0, 0)] / b0[(0, 0)] - 16.0).abs() < 1e-12);
    assert!((b[(3, 3)] / b0[(3, 3)] - 1.4).abs() < 1e-12);
    assert_eq!(b[(1, 1)], b0[(1, 1)]);
}

#[test]
fn motor_frame_makes_the_robot_torque_free() {
    let m = with("motor-frame");
    for c in cases() {
        let fb = m.force_balance(&c).unwrap();
        let v = fb.solve().unwrap();
        let mut tail_v = v;
        tail_v[3] += c.tail_rate_rad_s();
        let torque = (fb.body * v)[3] + (fb.tail * tail_v)[3];
        assert!(torque.abs() < 1e-12 * (fb.tail * tail_v)[3].abs());
        // The tail turns slower in the lab than the motor's rate: less counter-rotation.
        assert!(
            m.predict(&c).unwrap().omega_body_hz < Model::base().predict(&c).unwrap().omega_body_hz
        );
    }
}

#[test]
fn buoyancy_breaks_proportionality_and_pushes_up() {
    let m = with("buoyancy:net_force_mn=0.2");
    let c = &cases()[1];
    let p = m.predict(c).unwrap();
    let base = Model::base().predict(c).unwrap();
    assert!(p.u_mm_s > base.u_mm_s);
    let q = m
        .predict(&Case {
            frequency_hz: 2.0 * c.frequency_hz,
            ..c.clone()
        })
        .unwrap();
    assert!((q.u_mm_s / p.u_mm_s - 2.0).abs() > 1e-2);
}

#[test]
fn quadrature_model_agrees_with_exact_model_at_the_papers_resolution() {
    let mut q = preset("paper").unwrap();
    q.tail_method = TailMethod::Quadrature {
        nodes_per_wavelength: 100,
    };
    for c in cases() {
        let a = preset("paper").unwrap().predict(&c).unwrap();
        let b = q.predict(&c).unwrap();
        assert!((a.u_mm_s / b.u_mm_s - 1.0).abs() < 1e-3, "{}", c.id);
        assert!((a.omega_body_hz / b.omega_body_hz - 1.0).abs() < 1e-3);
    }
}

#[test]
fn time_integration_equals_the_direct_solve_for_the_papers_axial_runs() {
    let m = preset("paper").unwrap();
    for c in cases() {
        let direct = m.predict(&c).unwrap();
        let timed = integrate(&m, &c, TimeDomainSettings::default()).unwrap();
        assert!(
            (timed.u_mm_s / direct.u_mm_s - 1.0).abs() < 1e-8,
            "{}",
            c.id
        );
        assert!((timed.omega_body_hz / direct.omega_body_hz - 1.0).abs() < 1e-8);
    }
}

#[test]
fn six_dof_time_integration_agrees_with_phase_quadrature() {
    let mut m = with("motor-frame");
    m.dofs = Dofs::ALL;
    for c in cases().iter().take(3) {
        let timed = integrate(&m, c, TimeDomainSettings::default()).unwrap();
        let quad = phase_average(&m, c, 64).unwrap();
        assert!(
            (timed.u_mm_s / quad.u_mm_s - 1.0).abs() < 1e-7,
            "{}: {} vs {}",
            c.id,
            timed.u_mm_s,
            quad.u_mm_s
        );
        assert!((timed.omega_body_hz / quad.omega_body_hz - 1.0).abs() < 1e-7);
    }
}

#[test]
fn six_dof_solve_differs_from_axial_only_by_a_small_lateral_coupling() {
    let mut m = Model::base();
    m.dofs = Dofs::ALL;
    for c in cases() {
        let full = phase_average(&m, &c, 32).unwrap();
        let axial = Model::base().predict(&c).unwrap();
        let d = (full.u_mm_s / axial.u_mm_s - 1.0).abs();
        assert!(
            d < 0.2,
            "{}: 6-DOF {} vs axial {}",
            c.id,
            full.u_mm_s,
            axial.u_mm_s
        );
    }
}

#[test]
fn the_nonlocal_tail_method_and_the_nonlocal_tail_effect_agree() {
    let mut by_method = Model::base();
    by_method.tail_method = TailMethod::Stokeslets {
        segments_per_turn: 12,
    };
    let by_effect = with("nonlocal-tail");
    for c in cases() {
        let a = by_method.predict(&c).unwrap();
        let b = by_effect.predict(&c).unwrap();
        assert!((a.u_mm_s / b.u_mm_s - 1.0).abs() < 1e-12, "{}", c.id);
        assert!((a.omega_body_hz / b.omega_body_hz - 1.0).abs() < 1e-12);
        // Interaction along the helix lowers the local drag and thrust coupling.
        let local = Model::base().tail_matrix(&c).unwrap();
        let nonlocal = by_method.tail_matrix(&c).unwrap();
        assert!(nonlocal[(0, 0)] < local[(0, 0)] && nonlocal[(0, 3)].abs() < local[(0, 3)].abs());
    }
}

/// The paper's model with a constant multiplier `m` at `place`.
fn scaled(model: &Model, place: swimbot::effects::place::Place, m: f64) -> Model {
    use swimbot::effects::correction::{Form, LocatedCorrection};
    let c = LocatedCorrection::new(place, None, Form::Constant, 1.0, 1.0).unwrap();
    model.clone().with_effect(swimbot::effects::EffectInstance {
        effect: std::sync::Arc::new(c).into(),
        values: vec![m],
    })
}

/// Eq. 11 in the paper's drive splits into `U = (F - B_t[x,wx] omega) /
/// (D_x + B_t[x,x])` and `Omega_b = (T - B_t[wx,wx] omega) / E_x`: the
/// axial drags of body and tail and the thrust coupling set the speed
/// alone, and the speed sees the drags only through their sum. This is what
/// the verdict's readings of those places as one another rest on
/// (`discovery::interpret::equivalents`); with the motor's rate relative
/// to the body, the rotation does depend on them.
#[test]
fn the_speed_only_places_leave_the_rotation_and_see_the_drags_as_one_sum() {
    use swimbot::effects::place::Place;
    let base = Model::base();
    for c in cases() {
        let p = base.predict(&c).unwrap();
        for place in [Place::BodyTranslation, Place::TailDrag, Place::TailThrust] {
            let q = scaled(&base, place, 1.7).predict(&c).unwrap();
            assert!((q.u_mm_s / p.u_mm_s - 1.0).abs() > 1e-3, "{}", place.name());
            let rotation = (q.omega_body_hz / p.omega_body_hz - 1.0).abs();
            assert!(rotation < 1e-14, "{}: {rotation:e}", place.name());
        }
        // The body's drag times m is the tail's drag plus (m - 1) D_x.
        let fb = base.force_balance(&c).unwrap();
        let (d, b11) = (fb.body[(0, 0)], fb.tail[(0, 0)]);
        let m = 1.7;
        let on_body = scaled(&base, Place::BodyTranslation, m)
            .predict(&c)
            .unwrap();
        let on_tail = scaled(&base, Place::TailDrag, 1.0 + (m - 1.0) * d / b11)
            .predict(&c)
            .unwrap();
        assert!((on_body.u_mm_s / on_tail.u_mm_s - 1.0).abs() < 1e-12);
        // A motor rate relative to the body couples the two balances, weakly:
        // 0.06-0.6 % in the rotation on the paper's cases.
        let relative = with("motor-frame");
        let r = relative.predict(&c).unwrap();
        let s = scaled(&relative, Place::TailDrag, 1.7).predict(&c).unwrap();
        let coupled = (s.omega_body_hz / r.omega_body_hz - 1.0).abs();
        assert!((1e-4..1e-2).contains(&coupled), "{coupled:e}");
    }
}
