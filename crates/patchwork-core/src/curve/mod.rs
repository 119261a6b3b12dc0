//! Target curves: reading, validation, resampling, smoothing, splines, differential
//! geometry (κ, τ, Frenet and Bishop frames), comparison (DTW, shape error) and
//! preset curves.

mod differential;
mod dtw;
mod error;
mod frames;
mod noise;
mod polyline;
pub mod presets;
mod profile;
mod read;
mod shape_error;
mod smoothing;
mod spline;

pub use differential::{Analysis, AnalysisOptions, DerivativeScheme, analyse};
pub use dtw::dtw;
pub use error::{CurveError, Location};
pub use frames::{Frame, bishop_frames, frenet_frames};
pub(crate) use polyline::cumulative_length;
pub use polyline::{Curve, largest_gap};
pub use presets::{Preset, ReferenceCurve};
pub use profile::interpolate;
pub use read::{Units, points_from_json, read_curve, read_json, read_text};
pub use shape_error::{AlignedSamples, ShapeError, bend_and_twist, kabsch, shape_error};
pub use spline::{StrokeShape, seeded_stroke, seeded_stroke_shaped};

/// A point or vector in 3D, millimetres.
pub type Point = nalgebra::Vector3<f64>;
