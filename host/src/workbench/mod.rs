//! The model-vs-measurement workbench: compare a model with a dataset, find
//! where it fails, and test which physical effect explains the failure.
pub mod audit;
pub mod candidate;
pub mod compare;
pub mod data_quality;
pub mod diagnose;
pub mod diagnosis;
pub mod discovery;
pub mod experiments;
pub mod features;
pub mod fit;
pub mod headline;
pub mod input_covariance;
pub mod noise;
pub mod path;
pub mod plan;
pub mod progress;
pub mod propagate;
pub mod robust;
pub mod score;
pub mod search;
pub mod synth;
pub mod verdict;
