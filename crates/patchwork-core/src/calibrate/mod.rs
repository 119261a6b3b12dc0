//! Calibration: the balloon's material (and the patches') fitted to what a
//! lab measured on its own balloons, by least squares on the FE model:
//! - the bare balloon inflated: its length (clamp to tip) and diameter at
//!   one or more pressures ([`Inflation`]);
//! - the bare balloon's pressure–volume curve ([`PressureVolume`]);
//! - balloons built from designs, their centrelines measured inflated
//!   ([`Built`]): the only data that tells the patch's stiffness.
//!
//! The parameters fitted are chosen by the user ([`Parameter`]: the
//! modulus, the law's stiffening, the compressibility, the patch's
//! modulus); the others keep the starting materials' values. The misfits
//! are relative (predicted / measured − 1; a built centreline's distances
//! over its length), so every kind of value weighs alike. The answer states
//! each parameter's 95 % interval (from the residuals' scatter, Student's
//! t with m − n degrees of freedom), every residual, and warns where the
//! data cannot tell two parameters apart (|correlation| > 0.95).

mod answer;
mod built;
mod data;
mod error;
mod fit;
mod model;
mod parameters;
mod problem;
mod report;
mod run;

pub use answer::{BuiltFit, Calibration, Fitted, Residual};
pub use data::{Built, Inflation, Measurements, PressureVolume};
pub use error::CalibrationError;
pub use parameters::{Materials, Parameter};
pub use run::{CalibrationProgress, calibrate, calibrate_watched, check};

#[cfg(test)]
mod tests;
