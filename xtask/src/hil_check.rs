//! The host-side judgement of `cargo xtask hil` (`hil.rs`), kept apart so
//! that it is unit-tested without a board: the `INFO` line's fields, and
//! the fail-safe timing read back from a `hil-faults` image
//! (`firmware/src/hil_faults.rs`): the answer to `FAULT RESULT` parsed and
//! the gate's fall after an injected panic, hang or stack overflow held to
//! its bound.

use swimbot_shared::board::{PWM_FREQ_HZ, WAKE_PERIOD_US, WATCHDOG_MS};

/// Fields every `INFO` line carries (the log's, then the robot's).
const INFO_FIELDS: [&str; 8] = [
    "records=",
    "fw=",
    "commit=",
    "battery_mv=",
    "rate_mhz=",
    "fault=",
    "lockout=",
    "pairing=",
];

/// `line` is an `INFO` answer with every field.
pub fn check_info(line: &str) -> Result<(), String> {
    if !line.starts_with("swimbot-log v2 ") || !line.ends_with('\n') {
        return Err(format!("INFO line malformed: {:?}", line.trim_end()));
    }
    let missing: Vec<&str> = INFO_FIELDS
        .into_iter()
        .filter(|f| !line.split(' ').any(|w| w.starts_with(f)))
        .collect();
    if missing.is_empty() {
        Ok(())
    } else {
        Err(format!(
            "INFO line lacks {missing:?}: {:?}",
            line.trim_end()
        ))
    }
}

/// An injected fault.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Fault {
    Panic,
    Hang,
    Overflow,
}

impl Fault {
    pub const ALL: [Fault; 3] = [Fault::Panic, Fault::Hang, Fault::Overflow];

    /// The request line that injects it.
    pub fn request(self) -> &'static str {
        match self {
            Fault::Panic => "FAULT PANIC\n",
            Fault::Hang => "FAULT HANG\n",
            Fault::Overflow => "FAULT OVERFLOW\n",
        }
    }

    fn name(self) -> &'static str {
        match self {
            Fault::Panic => "panic",
            Fault::Hang => "hang",
            Fault::Overflow => "overflow",
        }
    }

    /// The reset that must follow: the panic handler forces one at once;
    /// a hang and an overflow (the core locks up, flip-link) are left to
    /// the watchdog.
    fn reset(self) -> &'static str {
        match self {
            Fault::Panic => "force",
            Fault::Hang | Fault::Overflow => "watchdog",
        }
    }

    /// Longest injection-to-last-fall time, us. Panic: the handler drives
    /// the gate low first, 1 ms is a pass. Hang, overflow: the watchdog
    /// period from the last feed, which was at most one pass
    /// (`WAKE_PERIOD_US`) before the injection, plus one PWM period (core
    /// 1 sees the last fall before the reset, the gate may be high for up
    /// to a period after it, until the reset lets the pull-down hold it).
    pub fn bound_us(self) -> u32 {
        let period_us = 1_000_000 / PWM_FREQ_HZ;
        match self {
            Fault::Panic => 1_000,
            Fault::Hang | Fault::Overflow => WATCHDOG_MS * 1_000 + WAKE_PERIOD_US + period_us,
        }
    }
}

/// What a `hil-faults` image recorded across its reset.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FaultResult {
    pub kind: String,
    pub injected_us: u32,
    pub gate_fall_us: u32,
    pub reset: String,
}

/// `FAULT RESULT kind=K injected_us=I gate_fall_us=F reset=R`.
pub fn parse_result(line: &str) -> Result<FaultResult, String> {
    let line = line.trim_end();
    let Some(rest) = line.strip_prefix("FAULT RESULT ") else {
        return Err(format!("not a FAULT RESULT answer: {line:?}"));
    };
    if rest == "none" {
        return Err("FAULT RESULT none: the image recorded no injection before its reset".into());
    }
    let field = |key: &str| -> Result<&str, String> {
        rest.split(' ')
            .find_map(|kv| kv.strip_prefix(key)?.strip_prefix('='))
            .ok_or_else(|| format!("FAULT RESULT lacks `{key}`: {line:?}"))
    };
    let number = |key: &str| -> Result<u32, String> {
        let v = field(key)?;
        v.parse()
            .map_err(|_| format!("FAULT RESULT `{key}` is not a number: {v:?}"))
    };
    Ok(FaultResult {
        kind: field("kind")?.to_string(),
        injected_us: number("injected_us")?,
        gate_fall_us: number("gate_fall_us")?,
        reset: field("reset")?.to_string(),
    })
}

/// The gate's last fall after the injection, us, if it is the fault's and
/// within its bound.
pub fn judge(fault: Fault, r: &FaultResult) -> Result<u32, String> {
    if r.kind != fault.name() {
        return Err(format!(
            "injected {}, the image recorded {}",
            fault.name(),
            r.kind
        ));
    }
    if r.gate_fall_us == 0 || r.gate_fall_us < r.injected_us {
        return Err(format!(
            "{}: no gate fall on GPIO17 after the injection (is the GPIO16-GPIO17 loopback wired?)",
            fault.name()
        ));
    }
    let low_us = r.gate_fall_us - r.injected_us;
    if r.reset != fault.reset() {
        return Err(format!(
            "{}: reset by {}, expected {} (gate low after {low_us} us)",
            fault.name(),
            r.reset,
            fault.reset()
        ));
    }
    if low_us > fault.bound_us() {
        return Err(format!(
            "{}: gate low {low_us} us after the injection, bound {} us",
            fault.name(),
            fault.bound_us()
        ));
    }
    Ok(low_us)
}

#[cfg(test)]
mod tests {
    use super::*;

    const INFO: &str = "swimbot-log v2 records=3 period_ms=100 dropped=0 foreign=0 paired=0x00 \
        log=this this_run=kept fw=0.1.0 commit=a0c77e4 battery_mv=3950 battery=ok rate_mhz=none \
        set_mhz=1000 fault=none trips=0 lockout=no pairing=paired\n";

    #[test]
    fn info_needs_every_field() {
        check_info(INFO).unwrap();
        let err = check_info(&INFO.replace("commit=a0c77e4 ", "")).unwrap_err();
        assert!(err.contains("commit="), "{err}");
        assert!(check_info("swimbot-log v1 records=3\n").is_err());
        assert!(
            check_info(INFO.trim_end()).is_err(),
            "a line without its newline"
        );
    }

    #[test]
    fn the_firmwares_own_info_line_passes() {
        use swimbot_shared::run_log::readout::info_line;
        use swimbot_shared::run_log::status::{PairingState, Status};
        use swimbot_shared::run_log::Header;
        let header = Header {
            sample_period_ms: 100,
            record_count: 3,
            dropped_records: 0,
            foreign_frames: 2,
            paired_address: Some(0x00),
            flags: 0,
        };
        let status = Status {
            firmware: "0.1.0",
            commit: "a0c77e4",
            battery_mv: 3_950,
            battery: swimbot_shared::BatteryLevel::Ok,
            rate_mhz: None,
            set_point_mhz: Some(1_000),
            fault: None,
            trips: 0,
            locked_out: false,
            pairing: PairingState::Paired,
        };
        let line = info_line(&header, Some(&status));
        check_info(std::str::from_utf8(&line).unwrap()).unwrap();
        // Without the robot's part (an older image) it fails.
        let line = info_line(&header, None);
        assert!(check_info(std::str::from_utf8(&line).unwrap()).is_err());
    }

    fn result(kind: &str, injected: u32, fall: u32, reset: &str) -> String {
        format!(
            "FAULT RESULT kind={kind} injected_us={injected} gate_fall_us={fall} reset={reset}\n"
        )
    }

    #[test]
    fn bounds_follow_the_board() {
        assert_eq!(Fault::Panic.bound_us(), 1_000);
        // 80 ms watchdog + a 1 ms pass + a 40 us PWM period.
        assert_eq!(Fault::Hang.bound_us(), 81_040);
        assert_eq!(Fault::Overflow.bound_us(), 81_040);
    }

    #[test]
    fn a_fault_within_its_bound_passes_and_one_past_it_fails() {
        let r = parse_result(&result("panic", 1_000_000, 1_000_012, "force")).unwrap();
        assert_eq!(judge(Fault::Panic, &r), Ok(12));
        let r = parse_result(&result("hang", 5_000, 5_000 + 81_040, "watchdog")).unwrap();
        assert_eq!(judge(Fault::Hang, &r), Ok(81_040));
        let r = parse_result(&result("hang", 5_000, 5_000 + 81_041, "watchdog")).unwrap();
        assert!(judge(Fault::Hang, &r)
            .unwrap_err()
            .contains("bound 81040 us"));
        let r = parse_result(&result("panic", 0, 1_001, "force")).unwrap();
        assert!(judge(Fault::Panic, &r).is_err());
    }

    #[test]
    fn the_wrong_kind_reset_or_no_edge_is_named() {
        let r = parse_result(&result("overflow", 9, 20, "force")).unwrap();
        assert!(judge(Fault::Overflow, &r)
            .unwrap_err()
            .contains("expected watchdog"));
        let r = parse_result(&result("hang", 9, 20, "watchdog")).unwrap();
        assert!(judge(Fault::Panic, &r)
            .unwrap_err()
            .contains("recorded hang"));
        let r = parse_result(&result("panic", 500, 0, "force")).unwrap();
        assert!(judge(Fault::Panic, &r).unwrap_err().contains("loopback"));
        let r = parse_result(&result("panic", 500, 400, "force")).unwrap();
        assert!(judge(Fault::Panic, &r).unwrap_err().contains("loopback"));
    }

    #[test]
    fn malformed_answers_are_refused() {
        assert!(parse_result("FAULT RESULT none\n")
            .unwrap_err()
            .contains("no injection"));
        assert!(parse_result("ERR unknown request\n").is_err());
        let err = parse_result("FAULT RESULT kind=panic injected_us=x gate_fall_us=1 reset=force")
            .unwrap_err();
        assert!(err.contains("injected_us"), "{err}");
        let err = parse_result("FAULT RESULT kind=panic injected_us=1 reset=force").unwrap_err();
        assert!(err.contains("gate_fall_us"), "{err}");
    }
}
