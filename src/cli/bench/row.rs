//! What a bench measures of one curve under one setting: its figures, the
//! reach verdict and the failures.

use patchwork_core::design::Design;
use patchwork_core::inverse::StageName;

/// One curve under one setting: medians over the runs.
pub struct Row {
    pub curve: String,
    pub setting: String,
    /// Medians over the runs (the most beyond limits).
    pub figures: Sample,
    /// Each finished run's figures, in the order of its seed.
    pub runs: Vec<Sample>,
    /// The reach stage's verdict: "yes", or the stretches out of reach.
    pub reach: String,
    pub failures: usize,
    /// Seconds each stage of the first finished run took, in the plan's
    /// order (empty when unknown).
    pub stages: Vec<(StageName, f64)>,
    /// The first finished run's design (none when no run finished).
    pub design: Option<Design>,
}

/// One run's figures (or their medians over the runs).
#[derive(Clone)]
pub struct Sample {
    pub wall_s: f64,
    pub evaluations: f64,
    pub shape_error_percent: f64,
    /// Shape error of the design on `REFERENCE_MESH`.
    pub reference_error_percent: f64,
    /// The same against the clean curve a drawn target was drawn from (NaN
    /// for the others).
    pub clean_error_percent: f64,
    pub dtw_curvature: f64,
    pub dtw_torsion: f64,
    pub patches: f64,
    pub beyond_limits: f64,
    /// Seconds of the run's spread stage (NaN without one), and the spread
    /// it found (% of the target's length).
    pub spread_s: f64,
    pub spread_percent: f64,
}

impl Sample {
    /// Every figure unknown (NaN).
    pub fn unknown() -> Sample {
        Sample {
            wall_s: f64::NAN,
            evaluations: f64::NAN,
            shape_error_percent: f64::NAN,
            reference_error_percent: f64::NAN,
            clean_error_percent: f64::NAN,
            dtw_curvature: f64::NAN,
            dtw_torsion: f64::NAN,
            patches: f64::NAN,
            beyond_limits: f64::NAN,
            spread_s: f64::NAN,
            spread_percent: f64::NAN,
        }
    }
}

/// The middle value (the upper of the two middle ones), NaN for none.
pub fn median(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    match values.len() {
        0 => f64::NAN,
        n => values[n / 2],
    }
}
