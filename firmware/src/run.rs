//! The main loop: IR edges -> commands, battery samples -> status, the
//! shared controller -> PWM duty, LED pattern, watchdog feed. A defmt line
//! for every state change (commands, controller events, battery level, LED
//! mode), so a probe log tells the whole story of a run.
//!
//! Between passes the core sleeps until an IR edge or the 1 kHz wake-up
//! alarm (`sleep`); timing comes from the 1 MHz timer, so a late pass only
//! delays, never distorts. The watchdog is fed only here, after a complete
//! pass, so a stall anywhere stops the feeding.

use crate::battery_adc::{BatterySense, SAMPLE_PERIOD_US};
use crate::board;
use crate::ir;
use crate::motor::Motor;
use crate::sleep;
use embedded_hal::digital::OutputPin;
use rp2040_hal::gpio::{bank0::Gpio25, FunctionSioOutput, Pin, PullDown};
use rp2040_hal::{Timer, Watchdog};
use swimbot_shared::{
    led, BatteryConfig, BatteryLevel, BatteryMonitor, Command, Controller, ControllerConfig,
    KeyMap, LedMode, Remote,
};

const _: () = assert!(board::LED_GPIO == 25, "the typed LED pin is GPIO25");

/// `hang-test`: stop feeding the watchdog this long after boot.
#[cfg(feature = "hang-test")]
const HANG_AFTER_US: u64 = 1_000_000;

pub type LedPin = Pin<Gpio25, FunctionSioOutput, PullDown>;

const KEYS: KeyMap = KeyMap {
    address: board::NEC_ADDRESS,
    on: board::NEC_CMD_ON,
    off: board::NEC_CMD_OFF,
};

pub struct Robot {
    motor: Motor,
    battery: BatterySense,
    led: LedPin,
    timer: Timer,
    remote: Remote,
    monitor: BatteryMonitor,
    controller: Controller,
}

impl Robot {
    pub fn new(motor: Motor, battery: BatterySense, led: LedPin, timer: Timer) -> Self {
        Self {
            motor,
            battery,
            led,
            timer,
            remote: Remote::new(KEYS),
            monitor: BatteryMonitor::new(BatteryConfig::new(
                board::DIVIDER_TOP_OHM,
                board::DIVIDER_BOTTOM_OHM,
                board::ADC_REF_MV,
            )),
            controller: Controller::new(ControllerConfig::DEFAULT),
        }
    }

    pub fn run(mut self, watchdog: &Watchdog) -> ! {
        let mut next_sample_us = self.timer.get_counter().ticks();
        let mut level = BatteryLevel::Fault;
        let mut led_mode = LedMode::Off;
        loop {
            let now_us = self.timer.get_counter().ticks();

            let mut command = None;
            while let Some(edge) = ir::pop() {
                if let Some(c) = self.remote.edge(edge.level, edge.t_us) {
                    defmt::info!("ir: {}", c);
                    command = Some(Command::merge(command, c));
                }
            }
            let dropped = ir::take_dropped();
            if dropped > 0 {
                defmt::warn!("ir: queue full, {} edges dropped", dropped);
            }

            if now_us >= next_sample_us {
                // Catch up without bursts if a pass was ever late.
                next_sample_us = now_us + SAMPLE_PERIOD_US;
                let counts = self.battery.read();
                let status = self.monitor.sample(counts, now_us, self.motor.is_on());
                if status.level != level {
                    level = status.level;
                    defmt::info!("battery: {} at {} mV ({} counts)", level, status.mv, counts);
                }
            }

            let battery = self.monitor.status();
            let out = self.controller.step(now_us, command, battery);
            self.motor.set(out.duty);
            if let Some(event) = out.event {
                defmt::info!(
                    "motor: {} -> {}, duty {}/65536, battery {} mV",
                    event,
                    out.state,
                    out.duty.raw(),
                    battery.mv
                );
            }

            let mode = LedMode::of(out.state, battery);
            if mode != led_mode {
                led_mode = mode;
                defmt::info!("led: {}", mode);
            }
            let _ = self.led.set_state(led::is_lit(mode, now_us).into());

            #[cfg(feature = "hang-test")]
            if now_us >= HANG_AFTER_US {
                defmt::warn!("hang-test: main loop stops, motor left as it is");
                #[allow(clippy::empty_loop)]
                loop {}
            }
            watchdog.feed();
            sleep::until_next_event();
        }
    }
}
