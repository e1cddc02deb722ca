//! New experiments inside the rig: what the rig can run ([`rig`]), the
//! measurement that best separates two models ([`separation`]), and what a
//! design with a field held fixed cannot separate ([`design`]).

pub mod design;
pub mod rig;
pub mod separation;
