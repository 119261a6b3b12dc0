//! Expert tuning: everything a preset fixes (meshes, budgets, patience, the
//! objective's form, the correction, the polish, where the search starts),
//! and the overrides an expert may lay over a preset. Users choose a
//! fidelity instead (`presets.rs`); the resolver (`plan.rs`) combines the
//! two.

use serde::{Deserialize, Serialize};

use super::objective::ObjectiveOptions;
use crate::fe::SimulateOptions;
use crate::fe::mesh::MeshSpec;
use crate::fe::newton::NewtonOptions;

/// The robust refine's solves when a request asks for it: about 30
/// evaluations of the design and its four largest sources' copies either
/// way.
pub const ROBUST_SOLVES: usize = 270;

/// Default initial CMA-ES step in the unit cube.
pub const INITIAL_STEP: f64 = 0.2;

/// Rod evaluations that count as one evaluation of the search's budget
/// and patience when it runs on the rod model: a rod evaluation, the
/// objective included, costs under a millisecond against tens to hundreds
/// for a search solve on FE.
pub const ROD_EVALUATIONS: usize = 10;

/// Every tuning value of a run. [`Default`] is a plain search: 600
/// evaluations on a uniform 2 mm model, verified on uniform 1 mm, with no
/// refine, correction or final refine; the presets set those.
#[derive(Debug, Clone, PartialEq)]
pub struct Tuning {
    /// Forward evaluations of the search, unless the user sets a budget.
    pub search_budget: usize,
    /// The search ends once this many evaluations have passed without
    /// improving its best design (0: never).
    pub search_patience: usize,
    /// CMA-ES's initial step σ₀ in the unit cube of the free variables (each
    /// variable's range maps to [0, 1]).
    pub initial_step: f64,
    /// Where CMA-ES starts: from KSA's patches (the method), or unseeded.
    pub start: Start,
    /// Start each search solve from the best design's inflated state instead
    /// of the candidate's own kinematic estimate (for CMA-ES-sized steps the
    /// kinematic start converges in fewer Newton iterations).
    pub warm_starts: bool,
    /// Search on the rod model (`crate::rod`: each candidate in about a
    /// tenth of a millisecond, from a table of one-patch FE solves kept
    /// for the scene, corrected by FE on the verification model at the
    /// seed and in rounds after, each patch's entry fitted to FE's rings),
    /// [`ROD_EVALUATIONS`] rod evaluations
    /// counting as one of the search's budget and patience, instead of FE
    /// solves on `search_mesh`.
    pub rod_search: bool,
    pub objective: ObjectiveOptions,
    pub search_mesh: MeshSpec,
    pub verify_mesh: MeshSpec,
    /// Cross-section rings of the centreline.
    pub rings: usize,
    /// KSA's curvature tolerance, merge distance and default width.
    pub kappa_tol: f64,
    pub merge_mm: f64,
    pub width_mm: f64,
    /// A KSA run longer than the longest patch the bounds allow
    /// (`h_max_mm`) becomes a train of patches within it; off: one patch
    /// per run however long (the authors' KSA).
    pub trains: bool,
    /// After the refine, try the layout with patches added where the
    /// target bends more gently than `kappa_tol` (`layout.rs`), refined
    /// like the design, and keep it if its shape error is lower.
    pub gentle_bends: bool,
    /// A planar target gets a planar design (`planar.rs`): its patches at
    /// Θ = 0 on one line of the tube and the line opposite, X and Θ kept
    /// fixed by the search and the refines.
    pub planar_designs: bool,
    /// After the design, its spread at the user's tolerances (every patch
    /// quantity and the balloon's three, linearised and the large ones
    /// solved both ways: the balloon's on the verification model, the
    /// patches' on `spread_patch_mesh`).
    pub spread: bool,
    /// The model the spread finds each patch's sources on (none: the
    /// verification model, as the balloon's): a coarser one, whose
    /// patches' changes agree with the verification model's, at a fraction
    /// of its solves' cost (`stages::spread`).
    pub spread_patch_mesh: Option<MeshSpec>,
    /// Designs the spread stage draws at the tolerances and solves in full
    /// to check its linear estimate (`crate::spread::monte_carlo`; 0: none).
    pub monte_carlo: usize,
    /// Keep the inflated tube clear of itself: the refines weigh every
    /// stretch of the tube that would pass through another (or come within
    /// half a millimetre of it) against the shape error, so a knot or a
    /// tight helix is designed as the balloon can inflate, at some cost in
    /// shape error where the target itself is tighter than the tube.
    pub keep_clear: bool,
    /// Solves of the robust refine after the spread (0: none): the design
    /// refined for the shape error expected at the tolerances
    /// (`stages::robust`), kept if that is lower than the nominal design's.
    pub robust_budget: usize,
    /// Evaluations of a CMA-ES polish on the verification model after the
    /// search (0 or 1: none). Not checkpointed: a resumed run repeats it.
    pub polish_budget: usize,
    /// Solves of the Levenberg–Marquardt refine on the shape error, the final
    /// refine's included (0: none). Not checkpointed.
    pub refine_budget: usize,
    /// The shape error (% of the target's length) at or below which the
    /// refines stop (the correction's rounds and the final refine too): the
    /// design is as close as asked, and steps beyond it follow the model's
    /// discretisation error more than the balloon (0: refine until a step
    /// gains less than 0.002 % or the budget is spent).
    pub refine_tolerance: f64,
    /// A finer model that corrects the refine's aim and verifies its result
    /// (output space mapping, `correction.rs`); none: the refine and the
    /// verification are the verification model's.
    pub correction_mesh: Option<MeshSpec>,
    /// A last refine on a finer model still, from the refine's result (and
    /// its Jacobian), on which the design is then verified.
    pub final_refine: Option<FinalRefineSettings>,
}

impl Default for Tuning {
    fn default() -> Self {
        Tuning {
            search_budget: 600,
            search_patience: 0,
            initial_step: INITIAL_STEP,
            start: Start::Ksa,
            warm_starts: false,
            rod_search: true,
            objective: ObjectiveOptions::default(),
            search_mesh: MeshSpec::uniform(2.0),
            verify_mesh: MeshSpec::uniform(1.0),
            rings: 72,
            kappa_tol: 0.01,
            merge_mm: 20.0,
            width_mm: 1.5,
            trains: false,
            gentle_bends: false,
            planar_designs: false,
            spread: false,
            spread_patch_mesh: None,
            monte_carlo: 0,
            keep_clear: false,
            robust_budget: 0,
            polish_budget: 0,
            refine_budget: 0,
            refine_tolerance: 0.0,
            correction_mesh: None,
            final_refine: None,
        }
    }
}

impl Tuning {
    /// The forward model on `mesh` with this run's rings.
    pub fn model(&self, mesh: MeshSpec) -> SimulateOptions {
        SimulateOptions {
            mesh,
            rings: self.rings,
            ..SimulateOptions::default()
        }
    }
}

/// The final refine: Levenberg–Marquardt on the shape error on `mesh`, from
/// the result of the refine on the verification model, which may spend at
/// most `staging_solves` of the refine budget (the final one the rest).
/// `newton` limits its model's solves. If that model cannot solve the
/// refine's result, the run does not fail: the refine's result stands,
/// verified on its own model, and the outcome says why.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FinalRefineSettings {
    pub mesh: MeshSpec,
    pub staging_solves: usize,
    pub newton: NewtonOptions,
}

impl FinalRefineSettings {
    /// The final refine's model: `tuning`'s on its mesh, with its Newton
    /// limits.
    pub fn model(&self, tuning: &Tuning) -> SimulateOptions {
        SimulateOptions {
            newton: self.newton,
            ..tuning.model(self.mesh)
        }
    }
}

/// Where the search starts.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Start {
    /// KSA's patches, with bounds as windows around them.
    #[default]
    Ksa,
    /// Unseeded, to measure what the seed is worth: as many patches as KSA
    /// found, spread evenly along the balloon with mid-range sizes, X = 0 and
    /// Θ = 0, each free over the whole balloon (X around the whole
    /// circumference, Y along the whole length, Θ within its limit). The
    /// balloon is the seeded run's (its length corrected from a simulation
    /// of KSA's seed), so that both starts search the same balloon.
    Even,
}

impl std::str::FromStr for Start {
    type Err = String;

    fn from_str(text: &str) -> Result<Self, Self::Err> {
        match text {
            "ksa" => Ok(Start::Ksa),
            "even" => Ok(Start::Even),
            _ => Err(format!("unknown start {text:?}: choose one of ksa, even")),
        }
    }
}

/// What an expert lays over a preset: each field given replaces the
/// preset's value. The CLI's research flags and the API's job options are
/// translated into this, so both front ends resolve through one path.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
/// Absent fields are left out when serialised (a stored job request reads
/// back as it was sent; the API refuses null).
#[serde(default, deny_unknown_fields)]
pub struct TuningOverrides {
    #[serde(skip_serializing_if = "Option::is_none")]
    pub search_patience: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub initial_step: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub start: Option<Start>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub warm_starts: Option<bool>,
    /// Whether the search runs on the rod model (true) or on FE solves.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rod_search: Option<bool>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub objective: Option<ObjectiveOptions>,
    /// Uniform meshes of this element size for the search, half of it for
    /// the refine and the verification, with no correction and no final
    /// refine (applied before the other mesh fields).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub uniform_mesh_mm: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub polish_budget: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub refine_budget: Option<usize>,
    /// The shape error (%) at or below which the refines stop (0: none).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub refine_tolerance: Option<f64>,
    /// false: no correction of the refine by a finer model.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub correction: Option<bool>,
    /// false: no final refine.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub final_refine: Option<bool>,
    /// Whether long KSA runs become trains of patches within the bounds.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub trains: Option<bool>,
    /// Whether the layout with patches on gentle bends is tried.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gentle_bends: Option<bool>,
    /// Whether a planar target gets a planar design.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub planar_designs: Option<bool>,
    /// false: no spread at the tolerances after the design.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub spread: Option<bool>,
    /// Samples of the Monte-Carlo check of the spread (0: none).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub monte_carlo: Option<usize>,
    /// true: the refines keep the tube clear of itself.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub keep_clear: Option<bool>,
    /// true: after the spread, the design refined for the shape error
    /// expected at the tolerances (`ROBUST_SOLVES` solves).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub robust: Option<bool>,
    /// KSA's curvature tolerance (mm⁻¹): bends gentler than this get no patch.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub kappa_tol: Option<f64>,
}

impl TuningOverrides {
    /// `tuning` with every given field replaced.
    pub fn apply(&self, mut tuning: Tuning) -> Tuning {
        if let Some(mesh_mm) = self.uniform_mesh_mm {
            tuning.search_mesh = MeshSpec::uniform(mesh_mm);
            tuning.verify_mesh = MeshSpec::uniform(mesh_mm / 2.0);
            tuning.correction_mesh = None;
            tuning.final_refine = None;
            tuning.spread_patch_mesh = None;
        }
        let set = |slot: &mut usize, value: Option<usize>| {
            if let Some(value) = value {
                *slot = value;
            }
        };
        set(&mut tuning.search_patience, self.search_patience);
        set(&mut tuning.polish_budget, self.polish_budget);
        set(&mut tuning.refine_budget, self.refine_budget);
        set(&mut tuning.monte_carlo, self.monte_carlo);
        tuning.initial_step = self.initial_step.unwrap_or(tuning.initial_step);
        tuning.refine_tolerance = self.refine_tolerance.unwrap_or(tuning.refine_tolerance);
        tuning.start = self.start.unwrap_or(tuning.start);
        tuning.warm_starts = self.warm_starts.unwrap_or(tuning.warm_starts);
        tuning.rod_search = self.rod_search.unwrap_or(tuning.rod_search);
        tuning.objective = self.objective.unwrap_or(tuning.objective);
        tuning.trains = self.trains.unwrap_or(tuning.trains);
        tuning.gentle_bends = self.gentle_bends.unwrap_or(tuning.gentle_bends);
        tuning.planar_designs = self.planar_designs.unwrap_or(tuning.planar_designs);
        tuning.spread = self.spread.unwrap_or(tuning.spread);
        tuning.keep_clear = self.keep_clear.unwrap_or(tuning.keep_clear);
        tuning.kappa_tol = self.kappa_tol.unwrap_or(tuning.kappa_tol);
        match self.robust {
            Some(true) => tuning.robust_budget = ROBUST_SOLVES,
            Some(false) => tuning.robust_budget = 0,
            None => {}
        }
        if self.correction == Some(false) {
            tuning.correction_mesh = None;
        }
        if self.final_refine == Some(false) {
            tuning.final_refine = None;
        }
        tuning
    }
}
