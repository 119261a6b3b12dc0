//! What the spread and its check compare: a design and its converged state,
//! and how far another centreline lies from it.

use crate::curve::{AlignedSamples, Curve};
use crate::design::Design;
use crate::fe::newton::NewtonOptions;
use crate::fe::newton::PatternCache;
use crate::fe::{SimulateOptions, Simulation};

/// Samples of the centreline compared.
pub const SAMPLES: usize = 64;

/// One source's change: the centreline's samples (mm, aligned) and the tip.
pub struct Change {
    /// Σ|dᵢ|² over the samples (mm²), and each |dᵢ|².
    pub samples_sq: f64,
    pub each_sq: Vec<f64>,
    pub tip_mm: f64,
}

/// A design and its converged state under `options`, and the tangent
/// patterns of its mesh that every moved design's solve shares (a design
/// run's own cache, so the spread, its check and a robust refine set each
/// mesh's pattern up once).
#[derive(Clone, Copy)]
pub struct Nominal<'a> {
    pub design: &'a Design,
    pub simulation: &'a Simulation,
    pub options: &'a SimulateOptions,
    pub patterns: &'a PatternCache,
}

/// The relative residual a moved design's solve stops at: looser than a
/// design's own solves (1e-9), since a spread needs each source's change
/// to a fraction of a percent, not the state to round-off. Measured on
/// four draft designs (hook, S, arc r80, grasp; graded 1 mm, one thread):
/// the spread's RMS within 0.06 % of the 1e-9 solves' and every
/// contributor above 5 % of the largest within 0.8 %, in 0.75–0.83 of the
/// time; at 1e-4 a contributor moved 12 %. On eight (conical spiral,
/// spring, hook, S, grasp, helix, Hilbert, trefoil): the RMS within
/// 0.16 %; every contributor above 5 % of the largest within 0.9 % on six,
/// but up to 5.4 % off on the Hilbert curve and 2.5 % on the trefoil,
/// whose six largest are within 0.2 % (docs/studies.md, "Newton steps
/// ring by ring").
pub const SOURCE_TOLERANCE: f64 = 1e-5;

impl Nominal<'_> {
    /// The options a moved design is solved with: the nominal's, its
    /// Newton tolerance loosened to [`SOURCE_TOLERANCE`] (never tightened).
    pub fn source_options(&self) -> SimulateOptions {
        let newton = self.options.newton;
        SimulateOptions {
            newton: NewtonOptions {
                tolerance: newton.tolerance.max(SOURCE_TOLERANCE),
                ..newton
            },
            ..*self.options
        }
    }
}

/// How `moved` differs from `nominal`: Σ|dᵢ|² over the nominal's samples
/// after the best rigid alignment, and the tip's move unaligned.
pub fn change_of(moved: &Curve, nominal: &Curve, samples: &Curve) -> Result<Change, String> {
    let aligned = AlignedSamples::new(moved, samples).map_err(|e| e.to_string())?;
    let each_sq: Vec<f64> = aligned.residuals.iter().map(|r| r.norm_squared()).collect();
    let tip = |c: &Curve| c.points().last().copied();
    let (Some(moved), Some(home)) = (tip(moved), tip(nominal)) else {
        return Err("no centreline".into());
    };
    Ok(Change {
        samples_sq: each_sq.iter().sum(),
        each_sq,
        tip_mm: (moved - home).norm(),
    })
}
