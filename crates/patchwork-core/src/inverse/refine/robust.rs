//! The robust refine: Levenberg–Marquardt on the shape error expected under
//! the tolerances instead of the nominal one (tuning `robust`).
//!
//! With r(u) the refine's scaled residuals of the design at u (|r| is its
//! shape error in %) and r±ₖ(u) those of the same design with source k
//! moved by ±σₖ, its tolerance, the expected square of the shape error over
//! independent sources is to second order
//!
//! ```text
//! E|r|² ≈ |r(u)|² + Σₖ ½ (|r+ₖ(u) − r(u)|² + |r−ₖ(u) − r(u)|²)
//! ```
//!
//! the nominal's square plus the spread's, each source's change taken
//! either way (each centreline aligned onto the target by itself, which to
//! first order is the spread's change). One side alone, as the spread's
//! secant, would let the refine find designs whose response is flat on that
//! side and steep on the other; the two-point form sees both. Stacking
//! R(u) = [r(u); (r±ₖ(u) − r(u))/√2 for each k and sign] makes |R| the
//! expected shape error over those sources: a least-squares problem the
//! refine's solver minimises as it does the nominal one. An evaluation
//! solves the nominal design and its moved copies, each warm-started from
//! its own previous state, in parallel; a Jacobian linearises each of them
//! (`fe::sensitivity`). The sources are the spread's largest (`RobustStage`
//! chooses them, with both signs): each copy costs a solve per evaluation,
//! and the small sources change little. The clearance residuals
//! (keep_clear) are the nominal design's only.

use std::sync::atomic::Ordering;

use nalgebra::{DMatrix, DVector};

use super::{RefineProblem, ShapeResiduals};
use crate::curve::Curve;
use crate::design::Design;
use crate::fe::Simulation;
use crate::fe::sensitivity::linearised_centrelines;
use crate::inverse::errors::DesignRunError;
use crate::least_squares::jacobian::stepped;
use crate::least_squares::{self, Iterate, Residuals, SpaceMapped};
use crate::parallel::map_in_threads;
use crate::spread::Source;

/// A design and its copies with each weighed source moved, inflated.
pub(in crate::inverse) struct Scenarios {
    pub nominal: Simulation,
    pub moved: Vec<Simulation>,
}

/// The robust refine's result: the design it reached (the start itself if
/// no step lowered the expected error), its scenarios, and the expected
/// error over the weighed sources before and after (%).
pub(in crate::inverse) struct RobustRefined {
    pub design: Design,
    pub scenarios: Scenarios,
    pub expected_before_percent: f64,
    pub expected_after_percent: f64,
    pub iterations: usize,
    /// FE solves: each evaluation solves every scenario, each Jacobian
    /// linearises every one (counted as a solve each).
    pub solves: usize,
}

/// The stacked residuals R of the module's doc over `sources` (each with
/// the amount it is moved by, in its tolerance's unit: every source twice,
/// at +σ and −σ).
struct Robust<'p> {
    shape: ShapeResiduals<'p>,
    sources: &'p [(Source, f64)],
}

impl Robust<'_> {
    fn moved(&self, design: &Design) -> Vec<Design> {
        let moved = self.sources.iter();
        moved.map(|(s, by)| s.moved(design, *by)).collect()
    }

    /// `designs` solved in parallel, each from its state in `nears`; none
    /// if any fails.
    fn solved<'s>(
        &self,
        designs: &[Design],
        nears: impl Iterator<Item = &'s Simulation>,
    ) -> Option<Vec<Simulation>> {
        let starts: Vec<(&Design, &Simulation)> = designs.iter().zip(nears).collect();
        let problem = self.shape.problem;
        let solved = map_in_threads(&starts, problem.threads, &|(design, near)| {
            (problem.caches)
                .simulate_from(design, problem.model, Some(near))
                .ok()
        });
        solved.into_iter().collect()
    }

    /// Each row of R from the nominal's residuals (its clearance's too) and
    /// the moved designs' centrelines.
    fn stacked(
        &self,
        nominal: DVector<f64>,
        moved: &[Option<DVector<f64>>],
    ) -> Option<DVector<f64>> {
        let shape_rows = self.shape.problem.shape_rows();
        let base = nominal.rows(0, shape_rows).clone_owned();
        let mut rows = nominal.as_slice().to_vec();
        for r in moved {
            let r = r.as_ref()?;
            rows.extend(
                (r - &base)
                    .iter()
                    .map(|d| d * std::f64::consts::FRAC_1_SQRT_2),
            );
        }
        Some(DVector::from_vec(rows))
    }
}

impl Residuals for Robust<'_> {
    type State = Scenarios;

    fn residuals(&self, state: &Scenarios) -> Option<DVector<f64>> {
        let problem = self.shape.problem;
        let nominal = problem.residuals_of(&state.nominal)?;
        let moved: Vec<_> = (state.moved.iter())
            .map(|s| problem.shape_residuals(&s.centreline))
            .collect();
        self.stacked(nominal, &moved)
    }

    fn solve(&self, u: &[f64], near: &Scenarios) -> Option<Scenarios> {
        let design = self.shape.design_at(u);
        let mut designs = vec![design.clone()];
        designs.extend(self.moved(&design));
        let nears = std::iter::once(&near.nominal).chain(&near.moved);
        let mut solved = self.solved(&designs, nears)?.into_iter();
        Some(Scenarios {
            nominal: solved.next()?,
            moved: solved.collect(),
        })
    }

    /// Each scenario's linearised responses to the stepped designs (its
    /// source moved alike), stacked as the residuals are. `None` when any
    /// scenario's tangent is not positive definite.
    fn cheap_jacobian(&self, at: &Iterate<Scenarios>, step: f64) -> Option<DMatrix<f64>> {
        let (points, steps): (Vec<Vec<f64>>, Vec<f64>) =
            (0..at.u.len()).map(|j| stepped(&at.u, j, step)).unzip();
        let designs: Vec<Design> = points.iter().map(|u| self.shape.design_at(u)).collect();
        let current = self.shape.design_at(&at.u);
        let problem = self.shape.problem;
        let (model, threads) = (problem.model, problem.threads);
        let patterns = &problem.caches.patterns;
        let responses = |base: &Design, state: &Simulation, changes: &[Design]| {
            linearised_centrelines(base, state, model, changes, threads, patterns)
        };
        let nominal = responses(&current, &at.state.nominal, &designs)?;
        let mut moved = Vec::with_capacity(self.sources.len());
        for ((source, by), state) in self.sources.iter().zip(&at.state.moved) {
            let changes: Vec<Design> = designs.iter().map(|d| source.moved(d, *by)).collect();
            moved.push(responses(&source.moved(&current, *by), state, &changes)?);
        }
        let here = self.residuals(&at.state)?;
        let radii = at.state.nominal.radii();
        let mut jacobian = DMatrix::zeros(here.len(), at.u.len());
        for (j, h) in steps.into_iter().enumerate() {
            let nominal = nominal[j]
                .as_ref()
                .and_then(|c| problem.residuals(c, &radii));
            let moved: Vec<_> = (moved.iter())
                .map(|m| {
                    m[j].as_ref()
                        .and_then(|c: &Curve| problem.shape_residuals(c))
                })
                .collect();
            if let Some(r) = nominal.and_then(|n| self.stacked(n, &moved)) {
                jacobian.set_column(j, &((r - &here) / h));
            }
        }
        Some(jacobian)
    }

    fn cancelled(&self) -> bool {
        self.shape.problem.cancel.load(Ordering::Relaxed)
    }

    fn out_of_time(&self) -> bool {
        self.shape.problem.deadline.passed()
    }
}

impl RefineProblem<'_> {
    /// Refines `start` (inflated on this problem's model as `nominal`) for
    /// the shape error expected under `sources`, each moved by its amount,
    /// with at most `budget` FE solves. `offset`, if given, is added to the
    /// nominal's residuals (a finer model's correction, as the refine's).
    pub fn refine_robust(
        &self,
        start: Design,
        nominal: Simulation,
        sources: &[(Source, f64)],
        (budget, offset): (usize, Option<&DVector<f64>>),
        on_progress: &mut dyn FnMut(usize, usize, &Simulation),
    ) -> Result<Option<RobustRefined>, DesignRunError> {
        let shape = ShapeResiduals::new(self, start)?;
        let robust = Robust { shape, sources };
        let u = robust.shape.start_point();
        // The start's copies, each from the start's state (the start itself
        // is solved).
        let copies = robust.moved(&robust.shape.design_at(&u));
        let Some(moved) = robust.solved(&copies, std::iter::repeat(&nominal)) else {
            return Ok(None);
        };
        let scenarios = Scenarios { nominal, moved };
        // The start's copies cost one solve each; an evaluation one per copy
        // and the design.
        let (first, per_evaluation) = (sources.len(), sources.len() + 1);
        let evaluations = budget.saturating_sub(first) / per_evaluation;
        let settings = least_squares::Settings {
            threads: self.threads,
            ..least_squares::Settings::default()
        };
        let mut progress =
            |i, e, s: &Scenarios| on_progress(i, first + e * per_evaluation, &s.nominal);
        // The nominal rows take the finer model's correction, if any; the
        // copies' changes are differences on this model (a zero offset).
        let rows = robust.residuals(&scenarios).map_or(0, |r| r.len());
        let mut padded = DVector::zeros(rows);
        if let Some(offset) = offset.filter(|o| o.len() <= rows) {
            padded.rows_mut(0, offset.len()).copy_from(offset);
        }
        let mapped = SpaceMapped {
            inner: &robust,
            offset: &padded,
        };
        let Ok(start) = Iterate::new(&mapped, u, scenarios) else {
            return Ok(None);
        };
        let solution =
            least_squares::minimise(&mapped, start, evaluations, None, &settings, &mut progress)
                .map_err(|least_squares::Cancelled| DesignRunError::Cancelled)?;
        Ok(Some(RobustRefined {
            design: robust.shape.design_at(&solution.best.u),
            scenarios: solution.best.state,
            expected_before_percent: solution.start_error,
            expected_after_percent: solution.best.error,
            iterations: solution.counts.iterations,
            solves: first + solution.counts.evaluations * per_evaluation,
        }))
    }
}
