//! The model-vs-measurement workbench: compare a model with a dataset, find
//! where it fails, and test which physical effect explains the failure.
pub mod audit;
pub mod audit_influence;
pub mod audit_loo;
pub mod audit_ratio;
pub mod compare;
pub mod design;
pub mod diagnose;
pub mod discovery;
pub mod features;
pub mod fit;
pub mod noise;
pub mod propagate;
pub mod synth;
pub mod verdict;
