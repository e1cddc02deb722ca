//! The brushed coreless DC motor: the `swimbot-motor` crate's model (its
//! equations, constants and integrators are documented there), one code
//! for this simulation and the emulator's rotor (WebAssembly).

pub use swimbot_motor::dc_motor::*;
