//! CMA-ES, the covariance matrix adaptation evolution strategy (Hansen &
//! Ostermeier 2001; Hansen 2016 tutorial), as in pycma/purecma: weighted
//! recombination, rank-one and rank-μ covariance updates, cumulative step-size
//! adaptation, default population 4 + ⌊3 ln n⌋, ask/tell, bounds by a smooth
//! transformation, IPOP restarts, a seeded random source, and serialisable state
//! for exact checkpoint and resume.
//!
//! - [`params`]: static parameters, computed once.
//! - [`strategy`]: the distribution and one ask/tell step.
//! - [`run`]: the loop — evaluation in parallel, termination, observers, restarts.

pub mod bounds;
pub mod params;
pub mod rng;
pub mod run;
pub mod strategy;

pub use bounds::{Bounds, BoundsError};
pub use rng::SeededRng;
pub use run::{Observer, Optimizer, Progress, RunOptions, RunResult, Termination};
pub use strategy::CmaEs;
