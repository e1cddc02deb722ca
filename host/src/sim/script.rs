//! The command script of `swimbot sim`: what the remote sends, and when.
//! Items are `on@0s`, `off@300s`, `nec:0x00:0x45@12.5s` (any address and
//! command byte), `repeat@1s` (an NEC repeat code), separated by commas,
//! semicolons or newlines; `#` starts a comment. Times take `ms`, `s` or
//! `min` (a bare number is seconds).
//!
//! Each item becomes the IR receiver's edge timestamps through the shared
//! crate's NEC encoder (`frame_pulses_us`, `for_each_edge`), the same
//! frames the firmware's decoder is fuzzed and tested with; the simulation
//! feeds them to the shared `Remote`. Frames closer than a frame's length
//! (~68 ms) overlap and garble, as they would in the air.

use swimbot_shared::nec::{for_each_edge, frame_pulses_us, REPEAT_PULSES_US};
use swimbot_shared::{KeyMap, Level};

/// What one script item sends.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Send {
    On,
    Off,
    Frame { address: u8, command: u8 },
    Repeat,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Item {
    pub at_us: u64,
    pub send: Send,
}

/// A parsed script, sorted by time.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Script {
    pub items: Vec<Item>,
}

#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("script item `{item}`: {message}")]
pub struct ScriptError {
    pub item: String,
    pub message: String,
}

impl Script {
    /// `on@0s`: the default, run until the channel's top or a stop.
    pub fn on_at_zero() -> Script {
        Script {
            items: vec![Item {
                at_us: 0,
                send: Send::On,
            }],
        }
    }

    pub fn parse(text: &str) -> Result<Script, ScriptError> {
        let mut items = Vec::new();
        for line in text.lines() {
            let line = line.split('#').next().unwrap_or("");
            for raw in line.split([',', ';']) {
                let item = raw.trim();
                if !item.is_empty() {
                    items.push(parse_item(item)?);
                }
            }
        }
        items.sort_by_key(|i: &Item| i.at_us);
        Ok(Script { items })
    }

    /// Time of the last item (µs), 0 for an empty script.
    pub fn end_us(&self) -> u64 {
        self.items.last().map_or(0, |i| i.at_us)
    }

    /// Every receiver edge of the script, sorted, absolute microseconds
    /// (the receiver's output idles high; a frame starts with a falling edge).
    pub fn edges(&self, keys: &KeyMap) -> Vec<(Level, u64)> {
        let mut edges = Vec::new();
        for item in &self.items {
            let pulses: Vec<u32> = match item.send {
                Send::On => frame_pulses_us(keys.address, keys.on).to_vec(),
                Send::Off => frame_pulses_us(keys.address, keys.off).to_vec(),
                Send::Frame { address, command } => frame_pulses_us(address, command).to_vec(),
                Send::Repeat => REPEAT_PULSES_US.to_vec(),
            };
            // Encode from 0 and offset in u64: a script may outlast the u32
            // microsecond counter (71 min), whose wrap the decoder handles.
            for_each_edge(0, &pulses, |level, t| {
                edges.push((level, item.at_us + u64::from(t)));
            });
        }
        edges.sort_by_key(|e| e.1);
        edges
    }
}

fn parse_item(item: &str) -> Result<Item, ScriptError> {
    let fail = |m: &str| ScriptError {
        item: item.to_string(),
        message: m.to_string(),
    };
    let (what, at) = item
        .split_once('@')
        .ok_or_else(|| fail("expected WHAT@TIME, e.g. on@0s or off@300s"))?;
    let at_us = parse_time_us(at.trim()).ok_or_else(|| {
        fail("the time must be a non-negative number with ms, s or min (e.g. 2.5s)")
    })?;
    let what = what.trim().to_ascii_lowercase();
    let send = match what.as_str() {
        "on" => Send::On,
        "off" => Send::Off,
        "repeat" => Send::Repeat,
        w if w.starts_with("nec:") => {
            let mut parts = w[4..].split(':');
            let (a, c) = (parts.next(), parts.next());
            match (a.and_then(parse_byte), c.and_then(parse_byte), parts.next()) {
                (Some(address), Some(command), None) => Send::Frame { address, command },
                _ => return Err(fail("expected nec:ADDRESS:COMMAND with bytes (0x45 or 69)")),
            }
        }
        _ => return Err(fail("expected on, off, repeat or nec:ADDRESS:COMMAND")),
    };
    Ok(Item { at_us, send })
}

fn parse_byte(s: &str) -> Option<u8> {
    let s = s.trim();
    match s.strip_prefix("0x") {
        Some(hex) => u8::from_str_radix(hex, 16).ok(),
        None => s.parse().ok(),
    }
}

pub(super) fn parse_time_us(s: &str) -> Option<u64> {
    let (num, scale) = if let Some(n) = s.strip_suffix("ms") {
        (n, 1e3)
    } else if let Some(n) = s.strip_suffix("min") {
        (n, 60e6)
    } else if let Some(n) = s.strip_suffix('s') {
        (n, 1e6)
    } else {
        (s, 1e6)
    };
    let v: f64 = num.trim().parse().ok()?;
    (v.is_finite() && v >= 0.0 && v * scale < 1e15).then(|| (v * scale).round() as u64)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_items_times_and_comments() {
        let s = Script::parse("off@5min, on@0s # start\nnec:0x01:71@250ms; repeat@1.5").unwrap();
        let got: Vec<(u64, Send)> = s.items.iter().map(|i| (i.at_us, i.send)).collect();
        assert_eq!(
            got,
            vec![
                (0, Send::On),
                (
                    250_000,
                    Send::Frame {
                        address: 1,
                        command: 71
                    }
                ),
                (1_500_000, Send::Repeat),
                (300_000_000, Send::Off),
            ]
        );
        for bad in ["on", "on@-1s", "go@1s", "nec:0x100:1@0s", "on@1h"] {
            assert!(Script::parse(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn a_frame_decodes_with_the_shared_remote() {
        let keys = KeyMap {
            address: 0,
            on: 0x45,
            off: 0x47,
        };
        let mut remote = swimbot_shared::Remote::new(keys);
        let s = Script::parse("on@1s,off@2s").unwrap();
        let got: Vec<_> = s
            .edges(&keys)
            .into_iter()
            .filter_map(|(l, t)| remote.edge(l, t as u32))
            .collect();
        assert_eq!(
            got,
            vec![swimbot_shared::Command::On, swimbot_shared::Command::Off]
        );
    }
}
