//! The non-local tail matrices (slender-body theory or regularized
//! Stokeslets) memoised for the model and the effects, which both sit
//! above this layer and ask for them (it lived in `model`, which made the
//! `nonlocal-tail` effect reach up into the model): one solve costs
//! milliseconds, and a fit or a diagnosis asks for the same geometry
//! thousands of times. The key is the exact bit pattern of every input.

use crate::nonlocal::{
    tail_resistance, NonlocalError, NonlocalSettings, TailMethod as NonlocalMethod,
};
use crate::physics::geometry::{Handedness, Helix};
use nalgebra::Matrix6;
use std::collections::HashMap;
use std::sync::{Mutex, OnceLock};

type Key = [u64; 10];

fn cache() -> &'static Mutex<HashMap<Key, Matrix6<f64>>> {
    static CACHE: OnceLock<Mutex<HashMap<Key, Matrix6<f64>>>> = OnceLock::new();
    CACHE.get_or_init(|| Mutex::new(HashMap::new()))
}

/// The non-local 6x6 tail matrix for `helix` in unbounded fluid.
pub fn nonlocal_tail(
    helix: &Helix,
    viscosity_pa_s: f64,
    method: NonlocalMethod,
    segments_per_turn: usize,
) -> Result<Matrix6<f64>, NonlocalError> {
    let key: Key = [
        helix.wavelength_m.to_bits(),
        helix.amplitude_m.to_bits(),
        helix.axial_length_m.to_bits(),
        helix.wire_diameter_m.to_bits(),
        u64::from(helix.handedness == Handedness::Right),
        helix.phase_rad.to_bits(),
        helix.joint_x_m.to_bits(),
        viscosity_pa_s.to_bits(),
        u64::from(method == NonlocalMethod::SlenderBody),
        segments_per_turn as u64,
    ];
    if let Some(m) = cache()
        .lock()
        .map_err(|_| NonlocalError::Settings("cache poisoned".into()))?
        .get(&key)
    {
        return Ok(*m);
    }
    let settings = NonlocalSettings::default()
        .with_method(method)
        .with_segments_per_turn(segments_per_turn);
    let m = tail_resistance(helix, viscosity_pa_s, &settings)?;
    if let Ok(mut c) = cache().lock() {
        c.insert(key, m);
    }
    Ok(m)
}
