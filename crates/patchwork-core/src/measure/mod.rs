//! From the bench back into the model: a built balloon's measured
//! centreline against its design's prediction and the target.
//!
//! [`Prediction`] is what a design run predicted (design.json's design, its
//! inflated centreline and the target as given); [`compare`] measures a
//! centreline taken off the built balloon against it: the shape error
//! against the prediction and against the target, the inflated length,
//! κ and τ along the length, and every patch's region — how far each bends
//! and twists against the prediction, and which diverges most.

mod compare;
mod error;
mod plot;
mod prediction;
mod regions;
pub mod scan;

pub(crate) use compare::oriented;
pub use compare::{
    ComparedProfiles, Comparison, MeasuredSummary, PROFILE_SAMPLES, RadiusFigures, ShapeFigures,
    compare, compare_scan, median_along,
};
pub use error::CompareError;
pub use plot::comparison_svg;
pub use prediction::Prediction;
pub use regions::PatchRegion;

#[cfg(test)]
mod tests;
