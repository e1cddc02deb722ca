//! The robot's decision logic, free of hardware: the IR remote protocol, the
//! command set, the motor controller state machine and the battery monitor.
//!
//! Everything here is `#![no_std]` without `alloc`, takes time as an argument
//! instead of reading a clock, and is therefore exercised identically by the
//! RP2040 firmware and by the host simulation and tests.
#![no_std]
#![forbid(unsafe_code)]
