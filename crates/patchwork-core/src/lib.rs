//! Patchwork's numerical core: target curves, the Kinematic Segmentation
//! Algorithm (KSA), the nonlinear membrane finite-element model, the solvers
//! (CMA-ES, Levenberg–Marquardt) and the inverse design that runs them.
//!
//! This crate is deliberately free of async, web and database dependencies so the
//! CLI, the HTTP service and the benchmarks all share one tested implementation.
//!
//! Units everywhere: millimetres, radians internally (degrees only at the JSON
//! boundary, named `*_deg`), curvature and torsion in mm⁻¹.

pub mod calibrate;
pub mod chart;
pub mod cmaes;
pub mod curve;
pub mod design;
pub mod fabrication;
pub mod fe;
pub mod inverse;
pub mod ksa;
pub mod least_squares;
pub mod material;
pub mod measure;
mod parallel;
pub mod rod;
pub mod spread;

pub use curve::{Curve, CurveError, Point};
pub use parallel::available_cores;
