//! The remote's rate keys: keys of the robot's own
//! remote select a preset tail rate or step the rate up or down. A key only
//! changes the set-point: it never starts the motor (On does), and repeat
//! frames (a key held) are never a key press, so holding a step key steps
//! once. Presets span the paper's observed rates, 0.57-1.50 Hz (Table II).
//!
//! The codes are those of the common 21-key NEC "car MP3" remote whose
//! CH- and CH+ keys are already On and Off (`board::KEYS`): digits 1-5 are
//! the presets, VOL+ and VOL- the steps.

/// What a set-point key asks for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum SetPointKey {
    /// Select this rate (mHz).
    Preset(u32),
    Faster,
    Slower,
}

/// Which command codes are set-point keys.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SetPointKeys {
    /// (command code, rate in mHz).
    pub presets: [(u8, u32); 5],
    pub faster: u8,
    pub slower: u8,
    /// One step of Faster or Slower (mHz).
    pub step_mhz: u32,
}

impl SetPointKeys {
    /// Keys 1-5: 0.50, 0.75, 1.00, 1.25, 1.50 Hz; VOL+/VOL-: +-0.05 Hz
    /// (5 % of the default 1 Hz, twice the controller's 2 % band, so a
    /// step is visible in the measured rate).
    pub const CAR_MP3: Self = Self {
        presets: [
            (0x0c, 500),
            (0x18, 750),
            (0x5e, 1_000),
            (0x08, 1_250),
            (0x1c, 1_500),
        ],
        faster: 0x15,
        slower: 0x07,
        step_mhz: 50,
    };

    /// The key for a command code of our remote, if it is one.
    pub fn lookup(&self, command: u8) -> Option<SetPointKey> {
        if command == self.faster {
            return Some(SetPointKey::Faster);
        }
        if command == self.slower {
            return Some(SetPointKey::Slower);
        }
        self.presets
            .iter()
            .find(|p| p.0 == command)
            .map(|p| SetPointKey::Preset(p.1))
    }

    /// The set-point after `key`, kept within `min_mhz..=max_mhz`. Without
    /// a set-point the steps have nothing to step from and change nothing.
    pub fn apply(
        &self,
        key: SetPointKey,
        set_mhz: Option<u32>,
        min_mhz: u32,
        max_mhz: u32,
    ) -> Option<u32> {
        let next = match (key, set_mhz) {
            (SetPointKey::Preset(f), _) => f,
            (_, None) => return None,
            (SetPointKey::Faster, Some(f)) => f.saturating_add(self.step_mhz),
            (SetPointKey::Slower, Some(f)) => f.saturating_sub(self.step_mhz),
        };
        Some(next.clamp(min_mhz, max_mhz.max(min_mhz)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    const K: SetPointKeys = SetPointKeys::CAR_MP3;

    #[test]
    fn keys_and_steps() {
        assert_eq!(K.lookup(0x5e), Some(SetPointKey::Preset(1_000)));
        assert_eq!(K.lookup(0x15), Some(SetPointKey::Faster));
        assert_eq!(K.lookup(0x45), None, "On is not a set-point key");
        assert_eq!(
            K.apply(SetPointKey::Faster, Some(1_000), 200, 2_000),
            Some(1_050)
        );
        assert_eq!(
            K.apply(SetPointKey::Slower, Some(210), 200, 2_000),
            Some(200)
        );
        assert_eq!(K.apply(SetPointKey::Faster, None, 200, 2_000), None);
        assert_eq!(
            K.apply(SetPointKey::Preset(500), None, 200, 2_000),
            Some(500)
        );
    }

    #[test]
    fn no_key_is_on_or_off() {
        let on_off = [crate::board::NEC_CMD_ON, crate::board::NEC_CMD_OFF];
        for code in on_off {
            assert_eq!(K.lookup(code), None);
        }
    }

    proptest! {
        #[test]
        fn always_within_range(code: u8, set in proptest::option::of(any::<u32>()), lo in 0u32..5_000, span in 0u32..5_000) {
            if let Some(k) = K.lookup(code) {
                if let Some(f) = K.apply(k, set, lo, lo + span) {
                    prop_assert!(f >= lo && f <= lo + span);
                }
            }
        }
    }
}
