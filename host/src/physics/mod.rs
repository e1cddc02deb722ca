//! The physics of the swimmer: geometry, local drag coefficients, resistance
//! matrices of the tail (eq. 3) and the body (eq. 10).
pub mod body;
pub mod coefficients;
pub mod geometry;
pub mod profile;
pub mod solve;
pub mod tail;
