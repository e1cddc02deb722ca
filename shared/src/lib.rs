//! The robot's decision logic, free of hardware: the IR remote protocol, the
//! command set, the motor controller state machine, the battery monitor, the
//! status LED patterns and the PWM carrier arithmetic.
//!
//! Everything here is `#![no_std]` without `alloc`, takes time as an argument
//! instead of reading a clock, and is therefore exercised identically by the
//! RP2040 firmware and by the host simulation and tests.
#![no_std]
#![forbid(unsafe_code)]

pub mod battery;
pub mod command;
pub mod controller;
pub mod led;
pub mod nec;
pub mod pwm;
pub mod rate;

pub use battery::{BatteryConfig, BatteryLevel, BatteryMonitor, BatteryStatus};
pub use command::{Command, KeyMap, Remote};
pub use controller::{Controller, ControllerConfig, Duty, Event, MotorState, Output, StopReason};
pub use led::LedMode;
pub use nec::{AddressFilter, Level, NecDecoder, NecEvent};
pub use pwm::PwmTiming;
