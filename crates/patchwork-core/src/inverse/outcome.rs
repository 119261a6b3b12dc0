//! What a design run reports: progress while it runs, and its outcome.

use std::time::Duration;

use serde::{Deserialize, Serialize};

use super::input::InputReport;
use super::layout::LayoutTrial;
use super::limits::AtLimit;
use super::reach::ReachReport;
use super::shortfall::Shortfall;
use crate::cmaes::Termination;
use crate::curve::Curve;
use crate::design::Design;
use crate::fe::Simulation;
use crate::fe::mesh::MeshSpec;
use crate::spread::Spread;

/// A stage's name: the one the plan lists it by (`Stage::name`), the
/// executor announces it by, and progress reports carry. Serialised in
/// snake case: `final_refine`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum StageName {
    /// KSA's patches and the balloon length they are placed on.
    Seed,
    /// What one patch makes within the bounds, against the target.
    Reach,
    /// CMA-ES on the search model.
    Search,
    /// The coarse-to-fine polish on the verification model.
    Polish,
    /// The design simulated on the verification model.
    Verify,
    /// The balloon length corrected to the target's.
    Length,
    /// Levenberg–Marquardt on the shape error.
    Refine,
    /// Patches added where the target bends gently, refined alike.
    Layout,
    /// The refine once more on the finest model.
    FinalRefine,
    /// The verified design at the tolerances, source by source.
    Spread,
    /// The design refined for the shape error expected at the tolerances.
    Robust,
}

impl StageName {
    /// Every stage, in the order a plan takes them.
    pub const ALL: [StageName; 11] = [
        StageName::Seed,
        StageName::Reach,
        StageName::Search,
        StageName::Polish,
        StageName::Verify,
        StageName::Length,
        StageName::Refine,
        StageName::Layout,
        StageName::FinalRefine,
        StageName::Spread,
        StageName::Robust,
    ];

    /// As written in plans and progress lines: `final refine`.
    pub fn as_str(self) -> &'static str {
        match self {
            StageName::Seed => "seed",
            StageName::Reach => "reach",
            StageName::Search => "search",
            StageName::Polish => "polish",
            StageName::Verify => "verify",
            StageName::Length => "length",
            StageName::Refine => "refine",
            StageName::Layout => "layout",
            StageName::FinalRefine => "final refine",
            StageName::Spread => "spread",
            StageName::Robust => "robust",
        }
    }
}

/// One stage's share of a run: its wall time and the forward solves it
/// counted (every stage's own; the search's include the seed's). The
/// reach stage's solves (its table's balloons, none when the table was
/// kept from an earlier run) are not in the run's `evaluations`, which
/// count against the budget.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct StageTime {
    pub stage: StageName,
    pub seconds: f64,
    pub evaluations: usize,
}

/// A run that its time limit cut short: the stage under way when the
/// limit passed, which stopped at its next step with its best design so
/// far, and the stages skipped after it (the verification is never
/// skipped: the design reported is always verified).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TimeLimited {
    pub limit_s: f64,
    pub reached_in: StageName,
    pub skipped: Vec<StageName>,
}

impl TimeLimited {
    /// In words, for the CLI and the web app: "60 s, reached in the refine;
    /// layout and spread skipped".
    pub fn message(&self) -> String {
        let reached = format!(
            "{} s, reached in the {}",
            self.limit_s,
            self.reached_in.as_str()
        );
        match self.skipped.is_empty() {
            true => reached,
            false => {
                let skipped: Vec<&str> = self.skipped.iter().map(|s| s.as_str()).collect();
                format!("{reached}; skipped: {}", skipped.join(", "))
            }
        }
    }
}

/// Progress reported to the observer.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct DesignProgress {
    pub stage: StageName,
    pub generation: usize,
    pub evaluations: usize,
    pub best_objective: f64,
    pub sigma: f64,
    pub elapsed_s: f64,
}

/// Why the search ended: CMA-ES's own stop, or the search's patience.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum SearchEnd {
    Optimizer(Termination),
    Search(SearchStop),
}

/// The search's own stops, beside CMA-ES's.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SearchStop {
    /// The best design did not improve within the search's patience.
    Stalled,
    /// The run's time limit passed (`UserSettings::time_limit_s`).
    TimeLimit,
}

impl SearchEnd {
    pub const STALLED: SearchEnd = SearchEnd::Search(SearchStop::Stalled);
    pub const TIME_LIMIT: SearchEnd = SearchEnd::Search(SearchStop::TimeLimit);
}

impl std::fmt::Display for SearchEnd {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SearchEnd::Optimizer(termination) => write!(f, "{termination:?}"),
            SearchEnd::Search(stop) => write!(f, "{stop:?}"),
        }
    }
}

/// How well the final design matches the target (on the model it was
/// verified on).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Metrics {
    pub objective: f64,
    pub dtw_curvature: f64,
    pub dtw_torsion: f64,
    pub shape_error_mm: f64,
    pub shape_error_percent: f64,
}

/// The verified centreline against the curve exactly as the user gave it,
/// before any smoothing or spline: [`Metrics`] measure it against the
/// prepared target the design aimed at, which smoothing may have moved
/// (rounded corners, jitter removed, a noisy stroke shortened) and a spline
/// through sparse points may have rounded. When neither applied both are
/// the same curve.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct AsGiven {
    /// Length of the polyline as given (jitter lengthens it).
    pub length_mm: f64,
    /// RMS distance after the best rigid alignment, at equal fractions of
    /// length, as [`Metrics::shape_error_mm`].
    pub shape_error_mm: f64,
    pub shape_error_percent: f64,
}

/// Target and verified κ, τ on the objective's sampling.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Profiles {
    pub target_curvature_per_mm: Vec<f64>,
    pub target_torsion_per_mm: Vec<f64>,
    pub curvature_per_mm: Vec<f64>,
    pub torsion_per_mm: Vec<f64>,
}

/// What a refine did, for the report: the shape error on its model (the
/// correction's model when there is one) before and after it, its accepted
/// steps and its solves.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct RefineSummary {
    pub shape_error_before_percent: f64,
    pub shape_error_after_percent: f64,
    pub iterations: usize,
    /// Fresh Jacobians, each counted as one solve when linearised (the
    /// other steps used Broyden-updated ones).
    #[serde(default)]
    pub jacobians: usize,
    /// Of those, the ones taken by forward differences (`variables` solves
    /// each), where the state's tangent was not positive definite.
    #[serde(default)]
    pub differenced_jacobians: usize,
    /// Solves on the refine's model (the correction's not counted), a
    /// linearised Jacobian counted as one.
    pub solves: usize,
    /// Free variables: the columns of a Jacobian.
    pub variables: usize,
    /// Element size of the finer model that corrected the refine and
    /// verified its result; absent when the refine ran uncorrected.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub corrected_on_element_mm: Option<f64>,
    /// Solves on that finer model.
    #[serde(default)]
    pub correction_solves: usize,
    /// The shape error (%) at or below which the refine stopped, the design
    /// then as close as asked (`refine_tolerance`; 0: none).
    #[serde(default)]
    pub tolerance_percent: f64,
}

/// The result of a design run.
#[derive(Debug, Clone)]
pub struct DesignOutcome {
    pub design: Design,
    pub seed_design: Design,
    /// The verified simulation of `design`.
    pub simulation: Simulation,
    /// Metrics of the verified simulation.
    pub metrics: Metrics,
    pub profiles: Profiles,
    /// Objective of the KSA seed and of the best design, both on the search
    /// model (comparable with each other, not with `metrics.objective`).
    pub seed_objective: f64,
    pub search_objective: f64,
    pub target_length_mm: f64,
    pub inflated_length_mm: f64,
    /// The uninflated balloon length to cut (= design.balloon.length_mm).
    pub uninflated_length_to_cut_mm: f64,
    pub evaluations: usize,
    pub termination: SearchEnd,
    /// What the refine did; none when it did not run.
    pub refine: Option<RefineSummary>,
    /// What the final refine on the finest model did (standard, fine); none
    /// when the plan has none, or when it could not start.
    pub final_refine: Option<RefineSummary>,
    /// Why a planned final refine did not run: its model could not solve
    /// the refine's result. The design, simulation and metrics are then the
    /// refine's, on `verified_on`.
    pub final_refine_skipped: Option<String>,
    /// The mesh of `simulation`, on which `metrics` were taken: the final
    /// refine's, the correction's (when the refine ran corrected) or the
    /// verification model's.
    pub verified_on: MeshSpec,
    /// Patch sizes and angles on (or beyond) a fabrication limit of the
    /// bounds: the target may want what the bounds forbid.
    pub at_limits: Vec<AtLimit>,
    /// What was done to the target before the design (its smoothing).
    pub input: InputReport,
    /// The verified centreline against the curve as given.
    pub as_given: AsGiven,
    /// The curve exactly as the user gave it (mm), before any smoothing.
    pub given: Curve,
    /// Where the target is beyond what a patch can make; none when the plan
    /// had no reach stage.
    pub reach: Option<ReachReport>,
    /// The layouts tried after the refine and what each reached; empty when
    /// the plan tried none.
    pub layouts: Vec<LayoutTrial>,
    /// Why the shape error is high, when it is (`shortfall.rs`).
    pub shortfalls: Vec<Shortfall>,
    /// The verified design's spread at the user's tolerances, against the
    /// target as given; none when the plan has no spread stage or it
    /// failed (`spread_failed` says why).
    pub spread: Option<Spread>,
    pub spread_failed: Option<String>,
    /// What the robust refine did (tuning `robust`), whether or not its
    /// design was kept; none when it did not run (`robust_skipped` says why
    /// where it was planned).
    pub robust: Option<RobustSummary>,
    pub robust_skipped: Option<String>,
    /// Why a search planned on the rod model (tuning `rod_search`) ran on
    /// FE instead: its table could not be solved, the time limit passed
    /// first, or the search's budget is too small for its rounds.
    pub rod_skipped: Option<String>,
    /// Each stage the run took in this process, in order, with its time.
    pub stage_times: Vec<StageTime>,
    pub elapsed: Duration,
    /// What the time limit cut short; none when the run finished within
    /// it (or had none).
    pub time_limited: Option<TimeLimited>,
}

/// What the robust refine did: the design the nominal refine found and the
/// robust refine's, each verified on the run's model against the curve the
/// design aims at, with its spread over every source.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RobustSummary {
    /// The sources it weighed, the spread's largest ("pressure", "P3 angle").
    pub sources: Vec<String>,
    pub nominal_design: Expected,
    pub robust_design: Expected,
    /// Whether the robust design replaced the nominal one: its expected
    /// shape error is lower.
    pub kept: bool,
    /// The expected shape error over the weighed sources only, on the
    /// refine's model (its objective), at its start and its end (%).
    pub weighed_before_percent: f64,
    pub weighed_after_percent: f64,
    pub iterations: usize,
    /// FE solves: the refine's, its result's verification and spread.
    pub solves: usize,
}

/// A design's shape error as designed, its spread at the tolerances, and
/// the shape error expected as built: √(nominal² + spread²), all in % of
/// the target's length.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Expected {
    pub shape_error_percent: f64,
    pub spread_percent: f64,
    pub expected_percent: f64,
}

impl Expected {
    /// These figures with the expected error from the other two.
    pub fn with_expected(self) -> Expected {
        Expected {
            expected_percent: self.shape_error_percent.hypot(self.spread_percent),
            ..self
        }
    }
}
