//! The seed: KSA's patches on a balloon whose length comes from mechanics
//! (or, on resumption, the checkpoint's state), evaluated on the search
//! model.

use super::super::caches::Caches;
use super::super::checkpoint::DesignCheckpoint;
use super::super::errors::DesignRunError;
use super::super::incumbent::score;
use super::super::run::{Context, Run, Setup};
use super::super::tuning::Start;
use super::super::variables::{DesignSpace, Freedom, VariableBounds};
use crate::curve::Curve;
use crate::design::{Design, Patch};
use crate::fe::tube_theory::inflate_tube;
use crate::ksa::{KsaParams, Stretch, ksa};

/// The first stage: it creates the run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Seed;

impl Seed {
    /// The run with its seed: from `resume` when given (a checkpoint of a
    /// run of the same target and plan), else KSA's seed, checkpointed.
    pub fn run<'a>(
        &self,
        setup: Setup<'a>,
        resume: Option<DesignCheckpoint>,
        ctx: &mut Context<'_>,
    ) -> Result<Run<'a>, DesignRunError> {
        let (settings, tuning) = (setup.settings, setup.tuning);
        let evaluate = |design: &Design| {
            score(
                ctx.caches,
                design,
                &setup.search_model,
                &setup.profiles,
                &tuning.objective,
                None,
            )
        };
        let (state, warm_start) = match resume {
            Some(mut state) => {
                // A checkpoint from before the patience existed does not
                // know when its best last improved: count from the resume,
                // so the search is not stopped at once.
                if state.improved_at == 0 {
                    state.improved_at = state.evaluations;
                }
                // The incumbent's state warms the next solves, as it did
                // before (one extra solve, only when warm starts are on).
                let warm = match tuning.warm_starts {
                    true => evaluate(&state.best_design()).1,
                    false => None,
                };
                (state, warm)
            }
            None => {
                let mut base = Design {
                    patches: vec![],
                    ..settings.base.clone()
                };
                base = seeded_balloon(base, settings.fix_length, &setup, ctx.caches)?;
                if tuning.start == Start::Even {
                    base.patches = spread_evenly(&base, base.patches.len(), &settings.bounds);
                }
                let seed_patches = std::mem::take(&mut base.patches);
                let seed_design = Design {
                    patches: seed_patches.clone(),
                    ..base.clone()
                };
                let (seed_objective, seed_simulation) = evaluate(&seed_design);
                let mut state = DesignCheckpoint {
                    base,
                    best_patches: seed_patches.clone(),
                    seed_patches,
                    seed_objective,
                    optimizer: None,
                    best_objective: seed_objective,
                    evaluations: 1,
                    improved_at: 1,
                    elapsed_s: 0.0,
                    rod: None,
                };
                ctx.checkpoint(&mut state);
                (state, seed_simulation)
            }
        };
        let space = design_space(&state, setup.freedom(), &settings.bounds, tuning.start)?;
        let mut run = Run::new(setup, state, space);
        run.warm_start = warm_start;
        Ok(run)
    }
}

/// How wide a design of the setup's target is likely to inflate: the 90th
/// percentile of the radii of KSA's seed's rings on the search model (the
/// widest stretches, bare ones included); none if the seed cannot be made
/// or solved.
pub(in crate::inverse) fn seed_tube_radius(setup: &Setup<'_>, caches: &Caches) -> Option<f64> {
    let base = Design {
        patches: vec![],
        ..setup.settings.base.clone()
    };
    let seeded = seeded_balloon(base, setup.settings.fix_length, setup, caches).ok()?;
    let simulation = caches
        .simulate_from(&seeded, &setup.search_model, None)
        .ok()?;
    let mut radii = simulation.radii();
    radii.sort_by(f64::total_cmp);
    radii.get(radii.len() * 9 / 10).copied()
}

/// The free variables around the seed, and the bounds they come from: the
/// user's around KSA's seed, the whole balloon for an unseeded start.
fn design_space(
    state: &DesignCheckpoint,
    freedom: Freedom,
    bounds: &VariableBounds,
    start: Start,
) -> Result<(DesignSpace, VariableBounds), DesignRunError> {
    let balloon = &state.base.balloon;
    let bounds = match start {
        Start::Ksa => *bounds,
        Start::Even => bounds.spanning(balloon.length_mm, balloon.radius_mm),
    };
    let space = DesignSpace::new(
        state.seed_patches.clone(),
        freedom,
        &bounds,
        balloon.length_mm,
    )
    .map_err(DesignRunError::Variables)?;
    Ok((space, bounds))
}

/// The balloon with its length chosen and the KSA seed as its patches.
fn seeded_balloon(
    base: Design,
    fix_length: bool,
    setup: &Setup<'_>,
    caches: &Caches,
) -> Result<Design, DesignRunError> {
    let target = setup.target;
    let b = &base.balloon;
    let state = inflate_tube(&b.material, base.pressure_mpa(), b.radius_mm, b.wall_mm).ok_or(
        DesignRunError::NoTubeState {
            pressure_kpa: base.pressure_kpa,
        },
    )?;
    let target_length = target.length();
    // Balloon length from mechanics: the bare tube stretches by λ₂ axially.
    let mut length = match fix_length {
        true => b.length_mm,
        false => target_length / state.axial,
    };
    let mut seed_patches = ksa_seed(target, &base, length, setup)?;
    if !fix_length {
        // Patches stretch less than bare wall, and the mesh is not the
        // membrane theory: correct the length once from a simulation of the
        // seed (even with no patches), scaling patch positions and lengths
        // with it. The length to cut comes from the most accurate model of
        // the run (the verification mesh): the coarse search mesh
        // overstates the bare tube's axial stretch by about 1 % and bends
        // a patch differently.
        let mut trial = Design {
            patches: seed_patches.clone(),
            ..base.clone()
        };
        trial.balloon.length_mm = length;
        let sim = caches
            .simulate(&trial, &setup.verify_model)
            .map_err(DesignRunError::Seed)?;
        trial.stretch_length(target_length / sim.inflated_length_mm);
        length = trial.balloon.length_mm;
        seed_patches = trial.patches;
        if setup.tuning.trains {
            // KSA at the corrected length is the stretched seed, except
            // that its trains are split for patch lengths on this balloon.
            seed_patches = ksa_seed(target, &base, length, setup)?;
        }
    }
    let circumference = base.balloon.circumference();
    let mut seeded = Design {
        patches: setup.laid_out(seed_patches, circumference),
        ..base
    };
    seeded.balloon.length_mm = length;
    Ok(seeded)
}

/// `count` patches spread evenly along the balloon: the unseeded start.
fn spread_evenly(balloon: &Design, count: usize, bounds: &VariableBounds) -> Vec<Patch> {
    let length = balloon.balloon.length_mm;
    (0..count)
        .map(|i| Patch {
            x_mm: 0.0,
            y_mm: (i as f64 + 0.5) * length / count as f64,
            h_mm: 0.5 * (bounds.h_min_mm + bounds.h_max_mm),
            w_mm: 0.5 * (bounds.w_min_mm + bounds.w_max_mm),
            theta_deg: 0.0,
        })
        .collect()
}

/// KSA patches for a balloon of `length`, mapping the whole target onto it.
fn ksa_seed(
    target: &Curve,
    base: &Design,
    length: f64,
    setup: &Setup<'_>,
) -> Result<Vec<Patch>, DesignRunError> {
    let params = KsaParams {
        l0_mm: length,
        r0_mm: base.balloon.radius_mm,
        stretch: Stretch::Fixed(target.length() / length),
        ..ksa_params(setup)
    };
    Ok(ksa(target, &params).map_err(DesignRunError::Ksa)?.patches)
}

/// The run's KSA settings: its tolerance, merge distance, width and trains
/// (the balloon's length and radius left at KSA's defaults).
pub(super) fn ksa_params(setup: &Setup<'_>) -> KsaParams {
    let tuning = setup.tuning;
    KsaParams {
        max_patch_mm: tuning.trains.then_some(setup.settings.bounds.h_max_mm),
        kappa_tol: tuning.kappa_tol,
        merge_mm: tuning.merge_mm,
        width_mm: tuning.width_mm,
        ..KsaParams::default()
    }
}
