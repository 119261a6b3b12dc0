//! What an FE solve of a whole design says the table gets wrong about each
//! of its patches: per patch, a factor on the table's curvature and shifts
//! of its twist, phase and stretch change ([`Correction`]), fitted so that
//! the corrected rod puts every ring's centre nearest FE's at the same
//! material height. The table knows each patch alone; a patch in a train,
//! or one whose neighbours bend the tube it sits on, differs, and the
//! correction carries that difference with the patch as a search moves it
//! (parameter extraction, where an offset of the centreline stays where it
//! was measured).
//!
//! Least squares over the unit cube of the corrections' ranges
//! (Levenberg–Marquardt, `crate::least_squares`), from no correction, with
//! a Tikhonov row per quantity (`PRIOR_MM` mm for a move across its whole
//! range) so that a quantity the rings cannot see (the twist of a patch
//! shorter than the rings' spacing) stays near none.

use std::f64::consts::FRAC_PI_2;

use nalgebra::DVector;
use serde::{Deserialize, Serialize};

use super::bare::BareTube;
use super::fit::{in_ranges, ring_gaps};
use super::integrate::{PatchRod, Placed};
use crate::design::Design;
use crate::fe::centreline::Ring;
use crate::least_squares::{Iterate, Residuals, Settings, minimise};

/// One patch's correction of its table entry.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Correction {
    /// Factor on the table's curvature.
    pub curvature_scale: f64,
    /// Added to the twist (rad per uninflated mm).
    pub twist: f64,
    /// Added to the phase (rad).
    pub phase: f64,
    /// Added to the stretch change.
    pub stretch: f64,
}

impl Correction {
    /// No correction: the table's entry as it is.
    pub const NONE: Correction = Correction {
        curvature_scale: 1.0,
        twist: 0.0,
        phase: 0.0,
        stretch: 0.0,
    };

    /// `rod` corrected.
    pub fn apply(&self, rod: PatchRod) -> PatchRod {
        PatchRod {
            curvature: rod.curvature * self.curvature_scale,
            twist: rod.twist + self.twist,
            phase: rod.phase + self.phase,
            stretch: rod.stretch + self.stretch,
        }
    }

    fn at(u: &[f64]) -> Correction {
        let q = in_ranges(u, &RANGES);
        Correction {
            curvature_scale: q[0],
            twist: q[1],
            phase: q[2],
            stretch: q[3],
        }
    }
}

/// The range of each quantity: curvature factor, twist (rad/mm), phase
/// (rad), stretch change.
const RANGES: [(f64, f64); 4] = [
    (0.25, 4.0),
    (-0.3, 0.3),
    (-FRAC_PI_2, FRAC_PI_2),
    (-1.0, 1.0),
];

/// The Tikhonov row's weight: mm of ring gap for a move across a
/// quantity's whole range.
const PRIOR_MM: f64 = 0.5;

/// Evaluations of the fit per corrected quantity.
const BUDGET_PER_QUANTITY: usize = 12;

/// The unit-cube point of no correction.
fn none_point(patches: usize) -> Vec<f64> {
    let none = [Correction::NONE.curvature_scale, 0.0, 0.0, 0.0];
    let one: Vec<f64> = (none.iter().zip(RANGES))
        .map(|(v, (lo, hi))| (v - lo) / (hi - lo))
        .collect();
    one.repeat(patches)
}

/// One design's rod against FE's rings.
struct Fit<'a> {
    bare: &'a BareTube,
    design: &'a Design,
    rods: &'a [PatchRod],
    rings: &'a [Ring],
    none: Vec<f64>,
}

impl Fit<'_> {
    fn corrections(u: &[f64]) -> Vec<Correction> {
        u.chunks(RANGES.len()).map(Correction::at).collect()
    }

    /// The corrected rod's centre minus FE's at every ring but the clamp's
    /// (mm, three per ring), then the prior's rows.
    fn gaps(&self, u: &[f64]) -> DVector<f64> {
        let placed: Vec<Placed> = (self.design.patches.iter())
            .zip(self.rods)
            .zip(Fit::corrections(u))
            .map(|((patch, rod), c)| Placed {
                patch: *patch,
                rod: c.apply(*rod),
            })
            .collect();
        let b = &self.design.balloon;
        let size = (b.radius_mm, b.length_mm);
        let mut gaps = ring_gaps(size, self.bare, &placed, self.rings);
        gaps.extend(u.iter().zip(&self.none).map(|(u, n)| PRIOR_MM * (u - n)));
        DVector::from_vec(gaps)
    }
}

impl Residuals for Fit<'_> {
    type State = DVector<f64>;

    fn residuals(&self, state: &DVector<f64>) -> Option<DVector<f64>> {
        Some(state.clone())
    }

    fn solve(&self, u: &[f64], _near: &DVector<f64>) -> Option<DVector<f64>> {
        Some(self.gaps(u))
    }
}

/// The corrections of `rods`, the table's entries of each of `design`'s
/// patches on a rod whose bare tube is `bare`, fitted to `rings`, FE's
/// rings of `design` (from the clamp, at ascending material heights); none
/// for every patch if there are fewer than three rings or the entries are
/// not one per patch.
pub fn fit_corrections(
    bare: &BareTube,
    design: &Design,
    rods: &[PatchRod],
    rings: &[Ring],
) -> Vec<Correction> {
    let n = design.patches.len();
    if rings.len() < 3 || n == 0 || rods.len() != n {
        return vec![Correction::NONE; n];
    }
    let fit = Fit {
        bare,
        design,
        rods,
        rings,
        none: none_point(n),
    };
    let u = fit.none.clone();
    let state = fit.gaps(&u);
    let Ok(start) = Iterate::new(&fit, u, state) else {
        return vec![Correction::NONE; n];
    };
    let settings = Settings {
        step: 1e-6,
        ..Settings::default()
    };
    let budget = BUDGET_PER_QUANTITY * fit.none.len();
    match minimise(&fit, start, budget, None, &settings, &mut |_, _, _| {}) {
        Ok(solution) => Fit::corrections(&solution.best.u),
        Err(_) => vec![Correction::NONE; n],
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::curve::Point;
    use crate::design::Patch;
    use crate::rod::integrate::centres;

    const ENTRY: PatchRod = PatchRod {
        curvature: 0.05,
        twist: 0.0,
        phase: 0.0,
        stretch: -1.0,
    };

    /// Rings of a design whose patches bend as the table says but for
    /// known corrections: the fit finds them again.
    #[test]
    fn the_fit_recovers_known_corrections() {
        let bare = BareTube::uniform(3.5);
        let patch = |x_mm: f64, y_mm: f64| Patch {
            x_mm,
            y_mm,
            h_mm: 20.0,
            w_mm: 2.0,
            theta_deg: 0.0,
        };
        let mut design = Design::reference(vec![patch(0.0, 40.0), patch(5.0, 90.0)]);
        design.balloon.length_mm = 130.0;
        let truth = [
            Correction {
                curvature_scale: 1.3,
                twist: 0.0,
                phase: 0.2,
                stretch: -0.1,
            },
            Correction {
                curvature_scale: 0.8,
                twist: 0.0,
                phase: -0.3,
                stretch: 0.05,
            },
        ];
        let placed: Vec<Placed> = (design.patches.iter().zip(&truth))
            .map(|(p, c)| Placed {
                patch: *p,
                rod: c.apply(ENTRY),
            })
            .collect();
        let heights: Vec<f64> = (1..=130).map(|k| k as f64).collect();
        let b = &design.balloon;
        let centres = centres(b.radius_mm, b.length_mm, &bare, &placed, &heights);
        let rings: Vec<Ring> = std::iter::once(Point::zeros())
            .chain(centres)
            .enumerate()
            .map(|(k, centre)| Ring {
                y: k as f64,
                centre,
                radius: 10.0,
            })
            .collect();
        let fitted = fit_corrections(&bare, &design, &[ENTRY; 2], &rings);
        for (f, t) in fitted.iter().zip(&truth) {
            // The prior pulls each quantity towards none by a little.
            assert!(
                (f.curvature_scale - t.curvature_scale).abs() < 0.02,
                "{f:?}"
            );
            assert!((f.phase - t.phase).abs() < 0.02, "{f:?}");
            assert!((f.stretch - t.stretch).abs() < 0.01, "{f:?}");
        }
    }
}
