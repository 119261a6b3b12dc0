use std::fmt;

/// Where in the user's input a problem sits: a line of a text file (1-based) or
/// an index into a JSON `points` array (0-based, as the user wrote it).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Location {
    Line(usize),
    Index(usize),
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Location::Line(line) => write!(f, "line {line}"),
            Location::Index(index) => write!(f, "points[{index}]"),
        }
    }
}

/// Everything that can be wrong with a target curve. Each variant carries the
/// numbers and positions a user needs to fix the input.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CurveError {
    #[error("curve has {found} distinct points, at least {min} are needed")]
    TooFewPoints { found: usize, min: usize },
    #[error("curve has {found} points, at most {max} are accepted")]
    TooManyPoints { found: usize, max: usize },
    #[error("{at}: coordinate {axis} is not finite ({value})")]
    NonFinite {
        at: Location,
        axis: char,
        value: f64,
    },
    #[error("{at}: column {column} is {value}, beyond ±1000000 (in the curve's units)")]
    OutOfRange {
        at: Location,
        column: usize,
        value: f64,
    },
    #[error("{at}: expected 3 columns (x y z), found {found}")]
    WrongColumnCount { at: Location, found: usize },
    #[error("{at}: column {column} is not a number: {text:?}")]
    NotANumber {
        at: Location,
        column: usize,
        text: String,
    },
    #[error("curve has zero total length (all points coincide)")]
    ZeroLength,
    #[error("invalid curve JSON: {0}")]
    Json(String),
    #[error("unknown units {0:?}: use mm, cm, m or in")]
    UnknownUnits(String),
    #[error("cannot resample to {requested} points: need between {min} and {max}")]
    ResampleCount {
        requested: usize,
        min: usize,
        max: usize,
    },
    #[error("preset parameter {name} = {value}: {reason}")]
    InvalidParameter {
        name: &'static str,
        value: f64,
        reason: &'static str,
    },
    #[error("smoothing length must be finite and ≥ 0 mm, got {0}")]
    InvalidSmoothing(f64),
    #[error(
        "smoothing σ = {sigma_mm} mm is more than a quarter of the curve's length \
         ({length_mm:.1} mm): it would smooth the curve flat"
    )]
    SmoothingTooLong { sigma_mm: f64, length_mm: f64 },
}
