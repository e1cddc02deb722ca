//! `pio` 0.3 without the `pio_asm!` and `pio_file!` macros.
//!
//! rp2040-hal 0.12 depends on `pio` for its PIO types only (`Program`,
//! `InstructionOperands`, ...), which `pio` re-exports from `pio-core`. The
//! real crate also always pulls in `pio-proc`, whose PIO assembler parser is
//! generated at build time by lalrpop: lalrpop, its regex and graph
//! dependencies and the generation run were about half the CPU time of a
//! cold firmware build, and they sat on its critical path. The firmware runs
//! no PIO program (PWM slice for the motor, GPIO interrupts for IR), so it
//! needs none of that. A firmware that wants `pio_asm!` deletes the
//! `[patch.crates-io]` entry in the workspace `Cargo.toml`; nothing else
//! changes.

#![no_std]

pub use pio_core::*;
