//! The search's rod model: the scene's rod table (`crate::rod`), from the
//! tables this process or the caller's store keeps (`inverse::memo`), else
//! solved on the verification model (72 one-patch balloons and a bare one
//! on the default bounds, about five seconds on two cores) and kept; and
//! its gap to FE at the seed, which corrects every candidate's centreline
//! (output space mapping, as the refine's correction: the rod's error is
//! mostly the same for designs near the seed, where the search looks). The
//! table's solves count in the search stage's time, not in its
//! evaluations; the seed's solve on the verification model is one
//! evaluation. A table that cannot be solved (a one-patch balloon fails)
//! leaves the search on FE.

use super::super::errors::DesignRunError;
use super::super::memo::{Kept, scene_key};
use super::super::run::{Context, Run};
use crate::curve::{Curve, CurveError, Point};
use crate::design::Design;
use crate::rod::{RodTable, axes};

/// The rod tables this process keeps.
static KEPT: Kept<RodTable> = Kept::new();

/// Points at equal fractions of length at which the rod is corrected.
const SAMPLES: usize = 200;

/// The rod the search scores its candidates on.
pub struct RodModel {
    pub table: RodTable,
    /// FE's centreline of the seed minus the rod's, at [`SAMPLES`] equal
    /// fractions of their lengths (zero where the seed has no FE state).
    offset: Vec<Point>,
}

impl RodModel {
    /// `design`'s rod centreline, corrected by the gap at the seed.
    pub fn centreline(&self, design: &Design) -> Result<Curve, CurveError> {
        let rod = self.table.centreline(design)?.resample(SAMPLES)?;
        let points = rod.points().iter().zip(&self.offset);
        Curve::from_points(points.map(|(p, d)| p + d).collect())
    }
}

/// The run's rod model; none if its table could not be solved.
pub(super) fn rod_model(
    run: &mut Run<'_>,
    ctx: &Context<'_>,
) -> Result<Option<RodModel>, DesignRunError> {
    let setup = &run.setup;
    let (base, bounds) = (&setup.settings.base, &setup.settings.bounds);
    let model = &setup.verify_model;
    let key = scene_key("rod table 1", base, bounds, model, &axes(bounds));
    let mut solves = 0;
    let compute = || {
        let [a, b, c] = axes(bounds);
        solves = 1 + a.len() * b.len() * c.len();
        RodTable::compute(base, bounds, model, setup.settings.threads, ctx.cancel)
    };
    let table = KEPT.table_for(&key, compute, |t| t.is_complete(bounds));
    ctx.check_cancelled()?;
    run.uncounted_solves += solves;
    let Ok(table) = table else {
        return Ok(None);
    };
    let seed = run.state.best_design();
    let fe = ctx.caches.simulate(&seed, model);
    run.state.evaluations += 1;
    let offset = fe.ok().and_then(|fe| {
        let fe = fe.centreline.resample(SAMPLES).ok()?;
        let rod = table.centreline(&seed).ok()?.resample(SAMPLES).ok()?;
        Some(
            fe.points()
                .iter()
                .zip(rod.points())
                .map(|(f, r)| f - r)
                .collect(),
        )
    });
    let offset = offset.unwrap_or_else(|| vec![Point::zeros(); SAMPLES]);
    Ok(Some(RodModel { table, offset }))
}
