//! `design.json`: the serialisable record of a design run, shared by the CLI
//! and the API.

use serde::{Deserialize, Serialize};

use super::input::InputReport;
use super::layout::LayoutTrial;
use super::limits::AtLimit;
use super::outcome::{
    AsGiven, DesignOutcome, Metrics, Profiles, RefineSummary, RobustSummary, SearchEnd, StageTime,
    TimeLimited,
};
use super::reach::ReachReport;
use super::shortfall::Explained;
use crate::design::Design;
use crate::fe::contact::{SelfContact, self_contacts};
use crate::spread::Spread;

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DesignReport {
    /// The design (same schema as `simulate`).
    pub design: Design,
    /// The predicted (verified) inflated centreline: the centres of rings
    /// at equal steps of the uninflated balloon's length, base to tip.
    pub centreline_mm: Vec<[f64; 3]>,
    /// The fitted radius of each ring of `centreline_mm` (mm); empty in
    /// reports written before it was kept.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub centreline_radius_mm: Vec<f64>,
    /// How far the inflated cap's pole lies past the last ring (mm): where
    /// a scan's centreline stops being the tube's; absent in reports
    /// written before it was kept.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cap_height_mm: Option<f64>,
    /// The target exactly as the user gave it (mm, before any smoothing):
    /// what `patchwork compare` measures a built balloon against; empty in
    /// reports written before it was kept.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub target_mm: Vec<[f64; 3]>,
    /// Verified on the fine mesh.
    pub metrics: Metrics,
    /// KSA seed and best design on the search model (comparable with each other).
    pub seed_objective: f64,
    pub search_objective: f64,
    pub target_length_mm: f64,
    pub inflated_length_mm: f64,
    /// inflated − target; non-zero mainly when the balloon length was fixed.
    pub length_mismatch_mm: f64,
    pub uninflated_length_to_cut_mm: f64,
    pub evaluations: usize,
    pub elapsed_s: f64,
    /// Each stage's wall time and forward solves, in the order run (this
    /// process's: a resumed run lists what it ran after resuming); empty
    /// in reports written before it was kept.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub stages: Vec<StageTime>,
    pub termination: SearchEnd,
    /// The refine's shape error before and after, steps and solves (absent
    /// when it did not run).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub refine: Option<RefineSummary>,
    /// The final refine on the finest model (standard's and fine's uniform
    /// 0.5 mm), from the refine's result; absent when the run had none.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub final_refine: Option<RefineSummary>,
    /// Why the run's final refine did not run (its model could not solve
    /// the refine's result; the design is then the refine's); absent when
    /// it ran or the run had none.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub final_refine_skipped: Option<String>,
    pub seed: u64,
    pub profiles: Profiles,
    /// Patch sizes and angles on (or beyond) a fabrication limit.
    #[serde(default)]
    pub at_limits: Vec<AtLimit>,
    /// What was done to the target before the design: the noise found, the
    /// smoothing applied, whether it is planar.
    #[serde(default)]
    pub input: InputReport,
    /// The verified centreline against the curve exactly as given (before
    /// smoothing), beside `metrics`, which are against the target the
    /// design aimed at; absent in reports written before it was measured.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub as_given: Option<AsGiven>,
    /// What one patch makes within the bounds, and where the target asks
    /// for more (empty `out_of_reach`: all of it is within reach).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reach: Option<ReachReport>,
    /// The layouts tried after the refine, what each reached, which was
    /// chosen; empty when none was tried.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub layouts: Vec<LayoutTrial>,
    /// Why the shape error is above 1 % of the length, when it is; absent
    /// otherwise.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub shortfalls: Vec<Explained>,
    /// Where the predicted inflated tube passes through itself (the model
    /// has no contact: the real balloon would push apart there); empty when
    /// it does not.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub self_contact: Vec<SelfContact>,
    /// How far the centreline moves under the tolerances the run was given
    /// (patch placement, angle and size; pressure, wall, modulus), its
    /// sources largest first; absent when the run had no spread stage.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub spread: Option<Spread>,
    /// Why the spread could not be found, when it could not.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub spread_failed: Option<String>,
    /// The robust refine's figures (tuning `robust`): the nominal and the
    /// robust design's shape error, spread and expected error, and which
    /// was kept; absent when the run had none.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub robust: Option<RobustSummary>,
    /// Why a planned robust refine did not run.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub robust_skipped: Option<String>,
    /// Why a search planned on the rod model ran on FE instead.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rod_skipped: Option<String>,
    /// Where the run's time limit (`time_limit_s`) cut it short: the stage
    /// under way, which stopped with its best design so far, and the stages
    /// skipped; absent when the run finished within its limit.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub time_limited: Option<TimeLimited>,
}

impl DesignReport {
    pub fn new(outcome: &DesignOutcome, seed: u64) -> DesignReport {
        DesignReport {
            design: outcome.design.clone(),
            centreline_mm: outcome
                .simulation
                .centreline
                .points()
                .iter()
                .map(|p| [p.x, p.y, p.z])
                .collect(),
            centreline_radius_mm: outcome.simulation.radii(),
            cap_height_mm: outcome.simulation.cap_height(),
            target_mm: outcome
                .given
                .points()
                .iter()
                .map(|p| [p.x, p.y, p.z])
                .collect(),
            metrics: outcome.metrics,
            seed_objective: outcome.seed_objective,
            search_objective: outcome.search_objective,
            target_length_mm: outcome.target_length_mm,
            inflated_length_mm: outcome.inflated_length_mm,
            length_mismatch_mm: outcome.inflated_length_mm - outcome.target_length_mm,
            uninflated_length_to_cut_mm: outcome.uninflated_length_to_cut_mm,
            evaluations: outcome.evaluations,
            elapsed_s: outcome.elapsed.as_secs_f64(),
            stages: outcome.stage_times.clone(),
            termination: outcome.termination,
            refine: outcome.refine,
            final_refine: outcome.final_refine,
            final_refine_skipped: outcome.final_refine_skipped.clone(),
            seed,
            profiles: outcome.profiles.clone(),
            at_limits: outcome.at_limits.clone(),
            input: outcome.input,
            as_given: Some(outcome.as_given),
            reach: outcome.reach.clone(),
            layouts: outcome.layouts.clone(),
            shortfalls: outcome.shortfalls.iter().map(Explained::from).collect(),
            self_contact: self_contacts(&outcome.simulation.rings),
            spread: outcome.spread.clone(),
            spread_failed: outcome.spread_failed.clone(),
            robust: outcome.robust.clone(),
            robust_skipped: outcome.robust_skipped.clone(),
            rod_skipped: outcome.rod_skipped.clone(),
            time_limited: outcome.time_limited.clone(),
        }
    }
}
