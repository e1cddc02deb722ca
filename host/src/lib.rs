//! `swimbot`: the host side of the swimbot project.
//!
//! The resistive-force-theory (RFT) model of the two-link helical swimmer of
//! Tabak & Yesilyurt's in-channel vertical swimming paper (section II.B,
//! eqs. 1-11), its built-in data (Tables I, II, IV), and the workbench that
//! compares the model with measurements.
pub mod atomic_dir;
pub mod atomic_file;
pub mod chart;
pub mod cli;
pub mod data;
pub mod effects;
pub mod format;
pub mod input_file;
pub mod model;
pub mod nonlocal;
pub mod physics;
pub mod progress;
pub mod provenance;
pub mod report;
pub mod robot;
pub mod runlog;
pub mod sim;
pub mod stats;
pub mod study;
pub mod workbench;
