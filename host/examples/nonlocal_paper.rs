//! Non-local resistance of the six paper tails, free and in the closed
//! 35 mm channel, with the body: `cargo run --release -p swimbot --example
//! nonlocal_paper [tube]` (the `tube` runs solve the leak-free MFS wall).
use std::time::Instant;
use swimbot::nonlocal::tube::{robot_resistance_in_tube, tail_resistance_in_tube, TubeSettings};
use swimbot::nonlocal::{robot_resistance, tail_resistance, NonlocalSettings, TailMethod};
use swimbot::physics::geometry::{Body, Channel, Helix};

fn main() {
    let mu = 3.5;
    let tube = std::env::args().any(|a| a == "tube");
    println!("tail  method  spt  N  B_xx[N s/m]  B_x,wx[N s]  B_wx,wx[N m s]  time[ms]");
    for (k, (l, b, lt)) in swimbot::data::paper_tails_mm().into_iter().enumerate() {
        let h = Helix::from_mm(l, b, lt, 1.0);
        for (m, spt) in [
            (TailMethod::RegularizedStokeslets, 12),
            (TailMethod::RegularizedStokeslets, 48),
            (TailMethod::SlenderBody, 12),
        ] {
            let s = NonlocalSettings::default()
                .with_method(m)
                .with_segments_per_turn(spt);
            let t0 = Instant::now();
            let r = tail_resistance(&h, mu, &s).unwrap();
            println!(
                "#{} {m:?} {spt} {} {:.5e} {:.5e} {:.5e} {:.1}",
                k + 1,
                s.tail_segments(&h),
                r[(0, 0)],
                r[(0, 3)],
                r[(3, 3)],
                t0.elapsed().as_secs_f64() * 1e3
            );
        }
    }
    if !tube {
        return;
    }
    let ch = Channel {
        diameter_m: 0.035,
        length_m: 1.0,
        closed: true,
        vertical: true,
    };
    let body = Body::from_mm(50.0, 20.0);
    let s = NonlocalSettings::default().with_segments_per_turn(12);
    for &k in &[5usize, 0] {
        let (l, b, lt) = swimbot::data::paper_tails_mm()[k];
        let h = Helix {
            joint_x_m: -0.030,
            ..Helix::from_mm(l, b, lt, 1.0)
        };
        let t0 = Instant::now();
        let free = tail_resistance(&h, mu, &s).unwrap();
        let ts = TubeSettings {
            tail: s,
            ..TubeSettings::default()
        };
        let conf = tail_resistance_in_tube(&h, &ch, mu, &ts).unwrap().matrix;
        println!(
            "#{} tail in tube / free: xx {:.4} x,wx {:.4} wx,wx {:.4} ({:.1} s)",
            k + 1,
            conf[(0, 0)] / free[(0, 0)],
            conf[(0, 3)] / free[(0, 3)],
            conf[(3, 3)] / free[(3, 3)],
            t0.elapsed().as_secs_f64()
        );
        for channel in [None, Some(&ch)] {
            let t0 = Instant::now();
            let r = match channel {
                None => robot_resistance(&body, &h, mu, &s).unwrap(),
                Some(ch) => robot_resistance_in_tube(&body, &h, ch, mu, &ts).unwrap().0,
            };
            let rig = r.rigid();
            println!("#{} robot {}: body xx {:.4e}, tail xx {:.4e}, coupling bt xx {:.4e}, rigid xx {:.4e}, tail x,wx {:.4e}, body wx,wx {:.4e} ({:.1} s)",
                k + 1, if channel.is_some() { "in tube" } else { "free" },
                r.body_body[(0, 0)], r.tail_tail[(0, 0)], r.body_tail[(0, 0)], rig[(0, 0)], r.tail_tail[(0, 3)], r.body_body[(3, 3)], t0.elapsed().as_secs_f64());
        }
    }
}
