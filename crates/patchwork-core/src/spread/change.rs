//! What the spread and its check compare: a design and its converged state,
//! and how far another centreline lies from it.

use crate::curve::{AlignedSamples, Curve, Point};
use crate::design::Design;
use crate::fe::newton::PatternCache;
use crate::fe::newton::{NewtonOptions, Steps};
use crate::fe::{SimulateOptions, Simulation};

/// Samples of the centreline compared.
pub const SAMPLES: usize = 64;

/// One source's change: the expected squares of the moves of the
/// centreline's samples (mm², aligned) and of the tip's, with the moves'
/// mean where the source was solved both ways.
///
/// Solved at +δ and −δ (moves d₊, d₋ at a sample), the response is read as
/// d(t) = a t + b t² with t = x/δ, a = (d₊ − d₋)/2, b = (d₊ + d₋)/2. For
/// x ~ N(0, δ²): E[d] = b and E|d|² = |a|² + 3|b|² (E t² = 1, E t³ = 0,
/// E t⁴ = 3). Solved one way, or linearised, the move d itself stands for
/// both: E|d|² = |d|² and no mean.
pub struct Change {
    /// Each sample's E|dᵢ|² (mm²).
    pub each_sq: Vec<f64>,
    /// √E|d|² of the tip's move (in the clamp's frame).
    pub tip_mm: f64,
    /// E[dᵢ] at each sample (empty: none), and the tip's.
    pub shift: Vec<Point>,
    pub tip_shift: Point,
}

impl Change {
    /// The change of a source whose response is this one's at `s` times
    /// its tolerance (`Source::equivalent`): with d(t) = a t + b t², the
    /// source at s δ reads a' = s a and b' = s² b, so
    /// E|d'|² = s² |a|² + 3 s⁴ |b|² with |a|² = E|d|² − 3 |b|², and a mean
    /// move s² b. A change without a mean (one way, linearised) scales by s.
    pub fn scaled(&self, s: f64) -> Change {
        let read = |sq: f64, b: &Point| {
            let odd_sq = (sq - 3.0 * b.norm_squared()).max(0.0);
            s * s * odd_sq + 3.0 * s.powi(4) * b.norm_squared()
        };
        self.reread(read, s * s)
    }

    /// This change read again point by point: each expected square (at
    /// every sample and at the tip) from `read`(its square, its mean
    /// move), and every mean move times `mean`.
    pub(super) fn reread(&self, read: impl Fn(f64, &Point) -> f64, mean: f64) -> Change {
        let none = Point::zeros();
        let each_sq = (self.each_sq.iter().enumerate())
            .map(|(i, &sq)| read(sq, self.shift.get(i).unwrap_or(&none)))
            .collect();
        Change {
            each_sq,
            tip_mm: read(self.tip_mm.powi(2), &self.tip_shift).max(0.0).sqrt(),
            shift: self.shift.iter().map(|b| b * mean).collect(),
            tip_shift: self.tip_shift * mean,
        }
    }
}

/// A moved centreline's offsets from the nominal: at each sample after
/// the best rigid alignment, and the tip's in the clamp's frame.
pub struct Offsets {
    pub residuals: Vec<Point>,
    pub tip: Point,
}

impl Change {
    /// Σᵢ E|dᵢ|² over the samples (mm²).
    pub fn samples_sq(&self) -> f64 {
        self.each_sq.iter().sum()
    }

    /// Its RMS over the samples (mm).
    pub fn rms_mm(&self) -> f64 {
        (self.samples_sq() / SAMPLES as f64).sqrt()
    }

    /// The change of a source solved (or linearised) one way only.
    pub fn one_way(moved: &Offsets) -> Change {
        let each_sq: Vec<f64> = moved.residuals.iter().map(|r| r.norm_squared()).collect();
        Change {
            each_sq,
            tip_mm: moved.tip.norm(),
            shift: Vec::new(),
            tip_shift: Point::zeros(),
        }
    }

    /// The change of a source solved at +δ (`plus`) and at −δ (`minus`).
    pub fn both_ways(plus: &Offsets, minus: &Offsets) -> Change {
        let expected_sq = |p: &Point, m: &Point| {
            let (odd, even) = ((p - m) / 2.0, (p + m) / 2.0);
            odd.norm_squared() + 3.0 * even.norm_squared()
        };
        let pairs = || plus.residuals.iter().zip(&minus.residuals);
        let each_sq: Vec<f64> = pairs().map(|(p, m)| expected_sq(p, m)).collect();
        Change {
            each_sq,
            tip_mm: expected_sq(&plus.tip, &minus.tip).sqrt(),
            shift: pairs().map(|(p, m)| (p + m) / 2.0).collect(),
            tip_shift: (plus.tip + minus.tip) / 2.0,
        }
    }
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
/// to a fraction of a percent, not the state to round-off. Its solves step
/// ring by ring (`Steps::Rings`, `fe::ring_step`: a rigid swing of the
/// tube costs no strain), which leaves so little residual along a swing
/// that a looser residual stops short of equilibrium even with the last
/// move bounded ([`SOURCE_STEP_MM`]): at 1e-6 the trefoil's wall moved
/// 2.5 % and the spring's P2 X 4 %. At 1e-7, on eleven draft designs (the
/// nine of the suite's, the robust arc and grasp; `patchwork spread`, 2
/// threads), every contributor above 5 % of the largest lies within
/// 0.05 % of its solves to 1e-10 and the RMS within 0.01 %, in 0.73–0.95
/// of the time the same solves take stepping linearly to 1e-5 (medians of
/// three: the conical spiral 0.73, the trefoil 0.81, the Hilbert 0.95) —
/// as close to the tight solves as those (docs/studies.md, "Newton steps
/// ring by ring").
pub const SOURCE_TOLERANCE: f64 = 1e-7;

/// The largest move (mm) of a moved design's last Newton iteration: at a
/// loose residual alone (1e-5, stepping linearly) a solve can stop along a long tube's soft
/// swing, its residual small and its state far from equilibrium. On the
/// spread tests' 120 mm design (wall −5 %, moving the centreline up to
/// 23 mm) the solve stopped 0.96 mm from the equilibrium started from the
/// reflected state and 1.44 mm started at second order; bounded at
/// 0.1 mm, both land within 1e-3 mm of it (8 and 4 iterations). On nine
/// draft designs of the suite the spread moved by at most 0.14 % and a
/// contributor by 0.5 % (`patchwork spread`, docs/studies.md "The spread's
/// solves").
pub const SOURCE_STEP_MM: f64 = 0.1;

impl Nominal<'_> {
    /// The options a moved design is solved with: the nominal's, its
    /// Newton tolerance loosened to [`SOURCE_TOLERANCE`] (never tightened),
    /// its steps ring by ring and its last move bounded by
    /// [`SOURCE_STEP_MM`].
    pub fn source_options(&self) -> SimulateOptions {
        let newton = self.options.newton;
        SimulateOptions {
            newton: NewtonOptions {
                tolerance: newton.tolerance.max(SOURCE_TOLERANCE),
                step_tolerance: newton.step_tolerance.min(SOURCE_STEP_MM),
                steps: Steps::Rings,
                ..newton
            },
            ..*self.options
        }
    }
}

/// How `moved` differs from `nominal`: its [`Offsets`] at the nominal's
/// samples.
pub fn offsets_of(moved: &Curve, nominal: &Curve, samples: &Curve) -> Result<Offsets, String> {
    let aligned = AlignedSamples::new(moved, samples).map_err(|e| e.to_string())?;
    let tip = |c: &Curve| c.points().last().copied();
    let (Some(moved), Some(home)) = (tip(moved), tip(nominal)) else {
        return Err("no centreline".into());
    };
    Ok(Offsets {
        residuals: aligned.residuals,
        tip: moved - home,
    })
}

/// `moved`'s change from `nominal` as one way's: Σ|dᵢ|² over the nominal's
/// samples after the best rigid alignment, and the tip's move unaligned.
pub fn change_of(moved: &Curve, nominal: &Curve, samples: &Curve) -> Result<Change, String> {
    offsets_of(moved, nominal, samples).map(|o| Change::one_way(&o))
}
