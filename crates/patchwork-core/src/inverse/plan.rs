//! The plan of a design run, and the resolver that makes it: (user
//! settings, preset, tuning overrides) → the complete tuning, checked field
//! by field → the list of stages. The CLI and the API both resolve through
//! [`Plan::resolve`], so the same request gives the same plan.
//!
//! A plan always reads, with the stages its tuning leaves out skipped:
//!
//! ```text
//! seed → reach → search → polish → verify → length → refine (± correction)
//!      → layout (a finer layout, refined alike) → final refine → spread
//!      → robust
//! ```

use super::errors::DesignRunError;
use super::errors::SettingsError;
use super::input::Smoothing;
use super::outcome::StageName;
use super::run::{Context, Run};
use super::settings::UserSettings;
use super::stages::{
    FinalRefine, Layout, Length, MAX_LAYOUTS, MAX_SOURCES, Polish, Reach, Refine, RobustStage,
    Search, Seed, SpreadStage, Verify,
};
use super::tuning::{Tuning, TuningOverrides};
use crate::spread::SOURCES_PER_PATCH;

/// One stage after the seed, with its own budget.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Stage {
    Reach(Reach),
    Search(Search),
    Polish(Polish),
    Verify(Verify),
    Length(Length),
    Refine(Refine),
    Layout(Layout),
    FinalRefine(FinalRefine),
    Spread(SpreadStage),
    Robust(RobustStage),
}

impl Stage {
    pub fn name(&self) -> StageName {
        match self {
            Stage::Reach(_) => StageName::Reach,
            Stage::Search(_) => StageName::Search,
            Stage::Polish(_) => StageName::Polish,
            Stage::Verify(_) => StageName::Verify,
            Stage::Length(_) => StageName::Length,
            Stage::Refine(_) => StageName::Refine,
            Stage::Layout(_) => StageName::Layout,
            Stage::FinalRefine(_) => StageName::FinalRefine,
            Stage::Spread(_) => StageName::Spread,
            Stage::Robust(_) => StageName::Robust,
        }
    }

    /// What the stage may spend, in words (`600 evaluations`), where its
    /// budget is its own: the search's and the polish's evaluations, the
    /// refines' solves. The other stages cost a few solves each.
    pub fn budget(&self) -> Option<String> {
        match self {
            Stage::Search(s) if s.patience > 0 => Some(format!(
                "{} evaluations, ends after {} without a better design",
                s.budget, s.patience
            )),
            Stage::Search(Search { budget, .. }) | Stage::Polish(Polish { budget }) => {
                Some(format!("{budget} evaluations"))
            }
            Stage::Refine(r) => Some(format!("{} solves", r.solves)),
            Stage::Layout(l) => Some(format!(
                "up to {MAX_LAYOUTS} layouts, {} solves each",
                l.refine.solves
            )),
            Stage::FinalRefine(f) => Some(format!(
                "{} solves with the refine's, on the {} model",
                f.shared_solves, f.refine.mesh
            )),
            Stage::Spread(s) => Some(format!(
                "{SOURCES_PER_PATCH} sources per patch and 3, at the tolerances: \
                 linearised, the large sources solved both ways{}{}",
                match s.patch_mesh {
                    Some(mesh) => format!(" (the patches' on the {mesh} model)"),
                    None => String::new(),
                },
                match s.monte_carlo {
                    0 => String::new(),
                    n => format!("; a Monte-Carlo check of {n} designs"),
                }
            )),
            Stage::Robust(r) => Some(format!(
                "{} solves, weighing the spread's {MAX_SOURCES} largest sources at most{}",
                r.solves,
                match r.monte_carlo {
                    0 => String::new(),
                    n => format!("; a Monte-Carlo check of {n} designs"),
                }
            )),
            Stage::Reach(_) | Stage::Verify(_) | Stage::Length(_) => None,
        }
    }

    /// Runs the stage on `run`, leaving its result there.
    pub(super) fn run(
        &self,
        run: &mut Run<'_>,
        ctx: &mut Context<'_>,
    ) -> Result<(), DesignRunError> {
        match self {
            Stage::Reach(stage) => stage.run(run, ctx),
            Stage::Search(stage) => stage.run(run, ctx),
            Stage::Polish(stage) => stage.run(run, ctx),
            Stage::Verify(stage) => stage.run(run, ctx),
            Stage::Length(stage) => stage.run(run, ctx),
            Stage::Refine(stage) => stage.run(run, ctx),
            Stage::Layout(stage) => stage.run(run, ctx),
            Stage::FinalRefine(stage) => stage.run(run, ctx),
            Stage::Spread(stage) => stage.run(run, ctx),
            Stage::Robust(stage) => stage.run(run, ctx),
        }
    }
}

/// A checked design run: the user's settings, the complete tuning, and the
/// stages they make. Only the resolver builds one, so every plan is valid.
#[derive(Debug, Clone, PartialEq)]
pub struct Plan {
    settings: UserSettings,
    tuning: Tuning,
    seed: Seed,
    stages: Vec<Stage>,
}

impl Plan {
    /// The plan of `settings` under its fidelity's preset with `overrides`
    /// laid over it.
    pub fn resolve(
        settings: UserSettings,
        overrides: &TuningOverrides,
    ) -> Result<Plan, SettingsError> {
        check_overrides(overrides)?;
        let preset = settings.fidelity.tuning(settings.base.balloon.radius_mm);
        let tuning = overrides.apply(preset);
        // A model's mesh is the preset's unless the expert set one: a
        // preset mesh fails only on a balloon too thin for it.
        let mesh_field = match overrides.uniform_mesh_mm {
            Some(_) => "tuning.uniform_mesh_mm",
            None => "design.balloon.radius_mm",
        };
        Plan::checked(settings, tuning, &|_| mesh_field.to_string())
    }

    /// The plan of `settings` with a complete `tuning` of the caller's (the
    /// settings' fidelity is then only a label).
    pub fn with_tuning(settings: UserSettings, tuning: Tuning) -> Result<Plan, SettingsError> {
        Plan::checked(settings, tuning, &|mesh| format!("tuning.{mesh}"))
    }

    /// The plan, its settings checked; a mesh that does not fit the balloon
    /// is blamed on the field `mesh_field` names for that model's mesh.
    fn checked(
        settings: UserSettings,
        tuning: Tuning,
        mesh_field: &dyn Fn(&str) -> String,
    ) -> Result<Plan, SettingsError> {
        check(&settings, &tuning, mesh_field)?;
        let stages = stages(&settings, &tuning);
        Ok(Plan {
            settings,
            tuning,
            seed: Seed,
            stages,
        })
    }

    pub fn settings(&self) -> &UserSettings {
        &self.settings
    }

    pub fn tuning(&self) -> &Tuning {
        &self.tuning
    }

    pub fn seed(&self) -> &Seed {
        &self.seed
    }

    /// The stages after the seed, in order.
    pub fn stages(&self) -> &[Stage] {
        &self.stages
    }

    /// The search's evaluations, the seed's included.
    pub fn search_budget(&self) -> usize {
        self.settings.budget.unwrap_or(self.tuning.search_budget)
    }

    /// Every evaluation the plan may spend: search, polish and refine.
    pub fn total_budget(&self) -> usize {
        self.search_budget() + self.tuning.polish_budget + self.tuning.refine_budget
    }

    /// The stage names, seed first: `seed → reach → search → verify → …`.
    pub fn describe(&self) -> String {
        std::iter::once(StageName::Seed)
            .chain(self.stages.iter().map(Stage::name))
            .map(StageName::as_str)
            .collect::<Vec<_>>()
            .join(" → ")
    }

    /// The stages after the seed with their budgets, `; `-separated:
    /// `reach; search: 600 evaluations; …`, and the whole run's time limit
    /// where it has one: `…; the whole run: at most 60 s`.
    pub fn describe_budgets(&self) -> String {
        let stages = self.stages.iter().map(|stage| match stage.budget() {
            Some(budget) => format!("{}: {budget}", stage.name().as_str()),
            None => stage.name().as_str().to_string(),
        });
        let limit = (self.settings.time_limit_s).map(|s| format!("the whole run: at most {s} s"));
        stages.chain(limit).collect::<Vec<_>>().join("; ")
    }
}

/// The stages of `tuning`, each with its budget. The refine on the
/// verification model spends at most the final refine's staging solves
/// when there is one, and the final refine the rest.
fn stages(settings: &UserSettings, tuning: &Tuning) -> Vec<Stage> {
    let mut stages = vec![Stage::Reach(Reach)];
    let budget = settings.budget.unwrap_or(tuning.search_budget);
    if budget > 1 {
        stages.push(Stage::Search(Search {
            budget,
            patience: tuning.search_patience,
            initial_step: tuning.initial_step,
        }));
    }
    if tuning.polish_budget > 1 {
        stages.push(Stage::Polish(Polish {
            budget: tuning.polish_budget,
        }));
    }
    stages.push(Stage::Verify(Verify));
    if !settings.fix_length {
        stages.push(Stage::Length(Length));
    }
    let refine_solves = match tuning.final_refine {
        Some(last) => tuning.refine_budget.min(last.staging_solves),
        None => tuning.refine_budget,
    };
    if refine_solves > 0 {
        let refine = Refine {
            solves: refine_solves,
            correction: tuning.correction_mesh,
        };
        stages.push(Stage::Refine(refine));
        if tuning.gentle_bends {
            stages.push(Stage::Layout(Layout { refine }));
        }
    }
    if let Some(refine) = tuning.final_refine {
        stages.push(Stage::FinalRefine(FinalRefine {
            refine,
            shared_solves: tuning.refine_budget,
        }));
    }
    // The Monte-Carlo check is of the design that stands: after the
    // robust refine where there is one.
    let robust = tuning.spread && tuning.robust_budget > 0;
    if tuning.spread {
        stages.push(Stage::Spread(SpreadStage {
            monte_carlo: if robust { 0 } else { tuning.monte_carlo },
            patch_mesh: tuning.spread_patch_mesh,
        }));
    }
    if robust {
        stages.push(Stage::Robust(RobustStage {
            solves: tuning.robust_budget,
            monte_carlo: tuning.monte_carlo,
        }));
    }
    stages
}

/// The finest uniform search mesh an expert may ask for (mm); the refine
/// and verification use half of it.
pub const MIN_UNIFORM_MESH_MM: f64 = 0.1;

/// The most designs a Monte-Carlo check of the spread may draw.
pub const MAX_MONTE_CARLO: usize = 5000;

/// The largest refine tolerance a request may set, % of the target's
/// length: a design that far off is no design.
pub const MAX_REFINE_TOLERANCE: f64 = 50.0;

/// The overrides' own ranges, before they are laid over a preset.
fn check_overrides(overrides: &TuningOverrides) -> Result<(), SettingsError> {
    if let Some(mesh_mm) = overrides.uniform_mesh_mm
        && !(mesh_mm.is_finite() && mesh_mm >= MIN_UNIFORM_MESH_MM)
    {
        return Err(SettingsError::new(
            "tuning.uniform_mesh_mm",
            format!("must be at least {MIN_UNIFORM_MESH_MM} mm, got {mesh_mm}"),
        ));
    }
    if let Some(samples) = overrides.monte_carlo
        && samples > MAX_MONTE_CARLO
    {
        return Err(SettingsError::new(
            "tuning.monte_carlo",
            format!("must be at most {MAX_MONTE_CARLO} designs, got {samples}"),
        ));
    }
    if let Some(kappa_tol) = overrides.kappa_tol
        && !(kappa_tol.is_finite() && kappa_tol > 0.0)
    {
        return Err(SettingsError::new(
            "tuning.kappa_tol",
            format!("must be a positive number, got {kappa_tol}"),
        ));
    }
    if let Some(tolerance) = overrides.refine_tolerance
        && !(tolerance.is_finite() && (0.0..=MAX_REFINE_TOLERANCE).contains(&tolerance))
    {
        return Err(SettingsError::new(
            "tuning.refine_tolerance",
            format!(
                "must be from 0 to {MAX_REFINE_TOLERANCE} (% of the target's length), got {tolerance}"
            ),
        ));
    }
    Ok(())
}

/// The longest time limit a run may be given: a week, in seconds.
pub const MAX_TIME_LIMIT_S: f64 = 604_800.0;

/// Every setting a run would otherwise fail on late, naming the field
/// (`mesh_field` names the field a model's mesh came from).
fn check(
    settings: &UserSettings,
    tuning: &Tuning,
    mesh_field: &dyn Fn(&str) -> String,
) -> Result<(), SettingsError> {
    crate::design::Design {
        patches: vec![],
        ..settings.base.clone()
    }
    .validate()
    .map_err(|e| SettingsError::new(format!("design.{}", e.field), e.reason))?;
    if tuning.robust_budget > 0 && !tuning.spread {
        return Err(SettingsError::new(
            "tuning.robust",
            "weighs the spread's sources: it needs the spread (tuning.spread is false)",
        ));
    }
    if settings.budget == Some(0) {
        return Err(SettingsError::new("budget", "must be at least 1"));
    }
    if let Smoothing::Sigma(sigma) = settings.smoothing
        && !(sigma.is_finite() && sigma >= 0.0)
    {
        return Err(SettingsError::new(
            "smoothing",
            format!("must be a non-negative number of millimetres, got {sigma}"),
        ));
    }
    if settings.threads == 0 {
        return Err(SettingsError::new("threads", "must be at least 1"));
    }
    if let Some(limit) = settings.time_limit_s
        && !(limit.is_finite() && limit > 0.0 && limit <= MAX_TIME_LIMIT_S)
    {
        return Err(SettingsError::new(
            "time_limit_s",
            format!(
                "must be a number of seconds above 0 and at most {MAX_TIME_LIMIT_S} (a week), got {limit}"
            ),
        ));
    }
    settings
        .tolerances
        .check()
        .map_err(|(field, reason)| SettingsError::new(format!("tolerances.{field}"), reason))?;
    settings
        .bounds
        .validate()
        .map_err(|e| SettingsError::new(format!("bounds.{}", e.field), e.to_string()))?;
    tuning.objective.validate().map_err(|(field, reason)| {
        SettingsError::new(format!("tuning.objective.{field}"), reason)
    })?;
    let step = tuning.initial_step;
    if !(step.is_finite() && step > 0.0 && step <= 1.0) {
        return Err(SettingsError::new(
            "tuning.initial_step",
            format!("must be in (0, 1] (a fraction of each variable's range), got {step}"),
        ));
    }
    let radius = settings.base.balloon.radius_mm;
    let meshes = [
        ("search_mesh", Some(tuning.search_mesh)),
        ("verify_mesh", Some(tuning.verify_mesh)),
        ("correction_mesh", tuning.correction_mesh),
        ("final_refine.mesh", tuning.final_refine.map(|f| f.mesh)),
        ("spread_patch_mesh", tuning.spread_patch_mesh),
    ];
    for (model, mesh) in meshes {
        if let Some(Err(reason)) = mesh.map(|m| m.validate(radius)) {
            return Err(SettingsError::new(mesh_field(model), reason));
        }
    }
    Ok(())
}

#[cfg(test)]
#[path = "plan_tests.rs"]
mod tests;
