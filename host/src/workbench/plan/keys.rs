//! A run's set-point as the keys the lab presses on the robot's remote
//! (the firmware's map, `swimbot_shared::board`: keys 1-5 select the
//! presets, VOL+ and VOL- step the rate, CH- is On and CH+ Off), and the
//! run's expected duration: the climb from the start (the whole robot
//! standing on its tail tip) to the tube's top at the predicted speed.

use crate::data::Case;
use swimbot_shared::board::{KEYS, SET_POINT_KEYS};

/// The label printed on the 21-key car-MP3 remote for a command code.
fn label(code: u8) -> String {
    let k = SET_POINT_KEYS;
    if let Some(i) = k.presets.iter().position(|p| p.0 == code) {
        return (i + 1).to_string();
    }
    match code {
        c if c == k.faster => "VOL+".into(),
        c if c == k.slower => "VOL-".into(),
        c if c == KEYS.on => "CH- (On)".into(),
        c if c == KEYS.off => "CH+ (Off)".into(),
        c => format!("0x{c:02x}"),
    }
}

/// The fewest presses that set `f_hz` (a preset, then steps), or `None`
/// when no preset and whole steps reach it.
pub fn set_point_keys(f_hz: f64) -> Option<Vec<String>> {
    let k = SET_POINT_KEYS;
    let target = (f_hz * 1e3).round() as i64;
    let step = i64::from(k.step_mhz);
    let (code, diff) = k
        .presets
        .iter()
        .map(|p| (p.0, target - i64::from(p.1)))
        .filter(|(_, d)| d % step == 0)
        .min_by_key(|(_, d)| d.abs())?;
    let n = (diff / step).unsigned_abs() as usize;
    let stepper = if diff > 0 { k.faster } else { k.slower };
    let mut out = vec![label(code)];
    out.extend(std::iter::repeat_n(label(stepper), n));
    Some(out)
}

/// The keys of one run: the set-point, then On; Off at the top.
pub fn run_keys(f_hz: f64) -> Option<String> {
    let mut keys = set_point_keys(f_hz)?;
    keys.push(label(KEYS.on));
    keys.push(label(KEYS.off));
    Some(keys.join(" "))
}

/// The climb's length: the tube less the robot standing in it.
fn climb_mm(c: &Case) -> f64 {
    c.channel_length_mm - (c.body_length_mm + c.coupler_length_mm + c.tail_length_mm)
}

/// Expected duration of the run at speed `u_mm_s` (`None`: no climb).
pub fn duration_s(c: &Case, u_mm_s: f64) -> Option<f64> {
    let t = climb_mm(c) / u_mm_s;
    (t.is_finite() && t > 0.0).then_some(t)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_preset_is_one_key_and_a_rate_between_is_a_preset_and_steps() {
        assert_eq!(set_point_keys(1.0).unwrap(), vec!["3"]);
        assert_eq!(set_point_keys(1.1).unwrap(), vec!["3", "VOL+", "VOL+"]);
        assert_eq!(set_point_keys(0.4).unwrap(), vec!["1", "VOL-", "VOL-"]);
        assert_eq!(
            set_point_keys(1.7).unwrap(),
            vec!["5", "VOL+", "VOL+", "VOL+", "VOL+"]
        );
        // 1.02 Hz is no whole number of 50 mHz steps from any preset.
        assert!(set_point_keys(1.02).is_none());
        assert_eq!(run_keys(1.25).unwrap(), "4 CH- (On) CH+ (Off)");
    }

    #[test]
    fn the_keys_replayed_through_the_firmwares_map_reach_the_set_point() {
        let k = SET_POINT_KEYS;
        for f_mhz in (200..=2000).step_by(50) {
            let keys = set_point_keys(f64::from(f_mhz) / 1e3).unwrap();
            let code = |l: &str| match l {
                "VOL+" => k.faster,
                "VOL-" => k.slower,
                d => k.presets[d.parse::<usize>().unwrap() - 1].0,
            };
            let mut set = None;
            for l in &keys {
                let key = k.lookup(code(l)).unwrap();
                set = k.apply(key, set, 200, 2000);
            }
            assert_eq!(set, Some(f_mhz), "{keys:?}");
        }
    }
}
