//! The search's rod model: the scene's rod table (`crate::rod`), from the
//! tables this process or the caller's store keeps (`inverse::memo`), else
//! solved on the verification model (72 one-patch balloons and a bare one
//! on the default bounds, about five seconds on two cores) and kept; and
//! its correction by FE at the seed (`rod_search.rs` corrects it again
//! where the search has moved). A correction fits each patch's table entry
//! to FE's rings (`rod::fit_corrections`: what its neighbours do to it
//! travels with the patch as the search moves it) and keeps the gap left
//! as an offset of the centreline, so that the corrected rod is FE at the
//! design corrected at. Nearby, the per-patch correction is what makes the
//! rod worth searching on: at CMA-ES-sized moves (σ 0.03 in the unit
//! cube) from twenty designs, the rod alone is 1.91 % of length from FE,
//! the rod plus the offset alone 1.19 %, the corrected rod plus its offset
//! 0.29 % (`cargo run --release -p patchwork-core --example rod_mapping --
//! 2 0.03`; docs/studies.md). The table's solves count in the search
//! stage's time and are bounded by the run's time limit, not counted in
//! its evaluations; the seed's solve on the verification model is one
//! evaluation. A resumed search's rod is corrected where the checkpoint
//! says it last was (`RodRounds`), which gives the same correction. A
//! table that cannot be solved (a one-patch balloon fails, or the time
//! limit passes first) leaves the search on FE, and the outcome's
//! `rod_skipped` says why.

use std::sync::atomic::Ordering;

use super::super::errors::DesignRunError;
use super::super::memo::{Kept, scene_key};
use super::super::objective::{ObjectiveOptions, TargetProfiles};
use super::super::run::{Context, Run};
use crate::curve::{Curve, CurveError, Point};
use crate::design::Design;
use crate::fe::Simulation;
use crate::rod::{Correction, RodTable, axes, fit_corrections};

/// The rod tables this process keeps.
static KEPT: Kept<RodTable> = Kept::new();

/// Points at equal fractions of length at which the rod is corrected.
const SAMPLES: usize = 200;

/// The rod the search scores its candidates on.
pub struct RodModel {
    pub table: RodTable,
    /// Each patch's correction of its table entry, fitted to FE at the
    /// design last corrected at (none before the first correction).
    corrections: Vec<Correction>,
    /// FE's centreline minus the corrected rod's there, at [`SAMPLES`]
    /// equal fractions of their lengths (zero before the first correction).
    offset: Vec<Point>,
}

impl RodModel {
    /// `design`'s rod centreline, each patch corrected as it was where the
    /// rod was last corrected, then moved by the gap left there.
    pub fn centreline(&self, design: &Design) -> Result<Curve, CurveError> {
        let rod = self.corrected(design)?;
        let points = rod.points().iter().zip(&self.offset);
        Curve::from_points(points.map(|(p, d)| p + d).collect())
    }

    /// `design`'s objective: its corrected centreline's, the tube of the
    /// bare radius throughout (none if the rod has no centreline).
    pub fn score(
        &self,
        design: &Design,
        profiles: &TargetProfiles,
        objective: &ObjectiveOptions,
    ) -> Option<f64> {
        let centreline = self.centreline(design).ok()?;
        Some(profiles.objective_of_rod(&centreline, self.table.bare.radius, objective))
    }

    /// Corrects the rod at `design` by FE's solve of it, `fe`: each patch's
    /// entry fitted to FE's rings ([`fit_corrections`]), then the gap left
    /// between the centrelines kept as an offset, so that `design`'s
    /// corrected centreline is FE's (the offset zero if the rod has no
    /// centreline there).
    pub fn correct_at(&mut self, design: &Design, fe: &Simulation) {
        let entries = self.table.entries(design);
        self.corrections = fit_corrections(&self.table.bare, design, &entries, &fe.rings);
        let gap = || {
            let fe = fe.centreline.resample(SAMPLES).ok()?;
            let rod = self.corrected(design).ok()?;
            let gap = fe.points().iter().zip(rod.points());
            Some(gap.map(|(f, r)| f - r).collect())
        };
        self.offset = gap().unwrap_or_else(|| vec![Point::zeros(); SAMPLES]);
    }

    /// `design`'s rod centreline with the corrections alone, at
    /// [`SAMPLES`] points.
    fn corrected(&self, design: &Design) -> Result<Curve, CurveError> {
        let rod = self.table.corrected_centreline(design, &self.corrections)?;
        rod.resample(SAMPLES)
    }
}

/// The run's rod model; none, and `run.rod_skipped` saying why, if its
/// table could not be solved or the time limit passed first.
pub(super) fn rod_model(
    run: &mut Run<'_>,
    ctx: &Context<'_>,
) -> Result<Option<RodModel>, DesignRunError> {
    let setup = &run.setup;
    let (base, bounds) = (&setup.settings.base, &setup.settings.bounds);
    let model = &setup.verify_model;
    let key = scene_key("rod table 1", base, bounds, model, &axes(bounds));
    let mut solves = 0;
    let (cancel, deadline) = (ctx.cancel, ctx.deadline);
    let stop = || cancel.load(Ordering::Relaxed) || deadline.passed();
    let compute = || {
        let [a, b, c] = axes(bounds);
        solves = 1 + a.len() * b.len() * c.len();
        RodTable::compute(base, bounds, model, setup.settings.threads, &stop)
    };
    let table = KEPT.table_for(&key, compute, |t| t.is_complete(bounds));
    ctx.check_cancelled()?;
    run.uncounted_solves += solves;
    let table = match table {
        Ok(table) if table.is_complete(bounds) => table,
        Ok(_) => {
            let why = "the run's time limit passed while the rod table's balloons were solved";
            run.rod_skipped = Some(why.into());
            return Ok(None);
        }
        Err(e) => {
            let why = format!("a balloon of the rod table did not solve: {e}");
            run.rod_skipped = Some(why);
            return Ok(None);
        }
    };
    let mut rod = RodModel {
        table,
        corrections: Vec::new(),
        offset: vec![Point::zeros(); SAMPLES],
    };
    // Where the search last corrected it (its solve counted then), else
    // at the seed.
    let at = match &run.state.rod {
        Some(rounds) => rounds.corrected_at.clone(),
        None => {
            run.state.evaluations += 1;
            run.state.best_patches.clone()
        }
    };
    let at = Design {
        patches: at,
        ..run.state.base.clone()
    };
    if let Ok(fe) = ctx.caches.simulate(&at, model) {
        rod.correct_at(&at, &fe);
    }
    Ok(Some(rod))
}
