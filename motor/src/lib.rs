//! The swimbot's motor as one model for every simulator: the brushed
//! coreless DC motor ([`dc_motor`]: `L di/dt = v - R i - k w`,
//! `J dw/dt = k i - b w - tau_c sgn(w) - tau_load`), and the motor turning
//! its tail with the Hall ring on its coupler ([`rotor`]: the tail's load
//! `tau_0 + c w` from the swimmer model, the quadrature edge pattern).
//!
//! `no_std` (`libm` for `tanh`/`cosh`) so that the same code runs in the
//! host's `swimbot sim` and, compiled to WebAssembly
//! (`motor/wasm`), under the RP2040 emulator's board: the chip's own
//! firmware is tested against the motor the host simulates.

#![no_std]

pub mod dc_motor;
pub mod rotor;

pub use dc_motor::{Motor, MotorParams, MotorRates, MotorState, FRICTION_SMOOTHING_RAD_S};
pub use rotor::{Crossing, Rotor, TailLoad, MAX_EDGES_PER_TURN};
