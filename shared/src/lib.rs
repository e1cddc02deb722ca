//! The robot's decision logic, free of hardware: the IR remote protocol, the
//! command set and the rate keys, the motor controller state machine, the
//! tail-rate sensing and control, the battery monitor, the
//! status LED patterns, the PWM carrier arithmetic, the board's constants,
//! the one main-loop pass that the chip, the host simulation and the
//! property tests all run, the run log's format and recorder, the USB
//! readout port's descriptors and control transfers, and what survives a
//! reset.
//!
//! Everything here is `#![no_std]` without `alloc`, takes time as an argument
//! instead of reading a clock, and is therefore exercised identically by the
//! RP2040 firmware and by the host simulation and tests.
#![no_std]
#![forbid(unsafe_code)]

pub mod battery;
pub mod board;
pub mod command;
pub mod controller;
pub mod led;
pub mod main_loop;
pub mod nec;
pub mod pairing;
pub mod pwm;
pub mod rate;
pub mod reset_memory;
pub mod run_log;
pub mod set_point;
pub mod supervisor;

pub use battery::{BatteryConfig, BatteryLevel, BatteryMonitor, BatteryStatus};
pub use command::{Command, KeyMap, PairedRemote, Remote, RemoteEvent};
pub use controller::{Controller, ControllerConfig, Duty, Event, MotorState, Output, StopReason};
pub use led::LedMode;
pub use main_loop::{
    ChipControl, HallEdge, MainLoop, MainLoopConfig, MotorControl, PassOutput, PreStart,
    SelfTestFault,
};
pub use nec::{AddressFilter, Level, NecDecoder, NecEvent};
pub use pairing::{Pairing, PairingConfig};
pub use pwm::PwmTiming;
pub use set_point::{SetPointKey, SetPointKeys};
pub use supervisor::{Supervisor, SupervisorConfig};
