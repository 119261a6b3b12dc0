//! The rod's centreline: the section frame and centre integrated along the
//! uninflated height (the formulas in `mod.rs`), each step by the midpoint
//! rule: half the turn, the move along the turned tangent, the other half.

use nalgebra::{Rotation3, Unit};
use serde::{Deserialize, Serialize};

use super::bare::BareTube;
use crate::curve::Point;
use crate::design::Patch;

/// What one patch does to the rod over its axial extent.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PatchRod {
    /// Bend per uninflated millimetre (rad/mm), towards the patch.
    pub curvature: f64,
    /// Turn of the bend's side round the tube per uninflated millimetre
    /// (rad/mm).
    pub twist: f64,
    /// The bend's side at the patch's middle, from the patch's centre (rad).
    pub phase: f64,
    /// Change of the centreline's axial stretch under the patch.
    pub stretch: f64,
}

/// A patch on the balloon and what it does to the rod.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Placed {
    pub patch: Patch,
    pub rod: PatchRod,
}

impl Placed {
    /// Whether height `y` lies within the patch's axial extent.
    fn covers(&self, y: f64) -> bool {
        (y - self.patch.y_mm).abs() <= self.patch.axial_half_extent()
    }
}

/// The longest step of the integration (uninflated mm).
pub const MAX_STEP_MM: f64 = 0.5;

/// The rod's centre at each uninflated height of `heights` (ascending, in
/// (0, length]), on a balloon of `radius` and `length` whose bare tube is
/// `bare`, carrying `placed`. The clamp's centre is the origin, its tangent
/// ẑ and its section axes x̂, ŷ (a patch at X = 0 lies towards x̂), as in the
/// FE mesh. Heights further apart than [`MAX_STEP_MM`] are reached in equal
/// steps no longer than it.
pub fn centres(
    radius: f64,
    length: f64,
    bare: &BareTube,
    placed: &[Placed],
    heights: &[f64],
) -> Vec<Point> {
    let (mut centre, mut frame) = (Point::zeros(), Rotation3::identity());
    let mut previous = 0.0;
    let mut out = Vec::with_capacity(heights.len());
    for &y in heights {
        let steps = ((y - previous) / MAX_STEP_MM - 1e-9).ceil().max(1.0);
        let dy = (y - previous) / steps;
        for _ in 0..steps as usize {
            let middle = previous + 0.5 * dy;
            previous += dy;
            let (stretch, curvature) = section(radius, length, bare, placed, middle);
            let half_turn = match Unit::try_new(Point::z().cross(&curvature), 1e-15) {
                Some(axis) => Rotation3::from_axis_angle(&axis, 0.5 * curvature.norm() * dy),
                None => Rotation3::identity(),
            };
            frame *= half_turn;
            centre += frame * Point::z() * (stretch * dy);
            frame *= half_turn;
        }
        previous = y;
        out.push(centre);
    }
    out
}

/// The axial stretch λ(y) and curvature vector k(y) at height `y`.
fn section(radius: f64, length: f64, bare: &BareTube, placed: &[Placed], y: f64) -> (f64, Point) {
    let mut stretch = bare.at(y, length);
    let mut curvature = Point::zeros();
    for p in placed.iter().filter(|p| p.covers(y)) {
        let phi = p.patch.x_mm / radius + p.rod.phase + p.rod.twist * (y - p.patch.y_mm);
        curvature += Point::new(phi.cos(), phi.sin(), 0.0) * p.rod.curvature;
        stretch += p.rod.stretch;
    }
    (stretch, curvature)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn uniform(stretch: f64) -> BareTube {
        BareTube::uniform(stretch)
    }

    fn patch(x_mm: f64, y_mm: f64, h_mm: f64) -> Patch {
        Patch {
            x_mm,
            y_mm,
            h_mm,
            w_mm: 0.0,
            theta_deg: 0.0,
        }
    }

    /// A bare rod is straight along ẑ, its length the stretch times the
    /// balloon's.
    #[test]
    fn a_bare_rod_is_straight() {
        let heights: Vec<f64> = (1..=100).map(|k| k as f64).collect();
        let c = centres(3.0, 100.0, &uniform(3.5), &[], &heights);
        assert!((c[99] - Point::new(0.0, 0.0, 350.0)).norm() < 1e-9);
    }

    /// One patch of constant curvature κ over the whole rod bends it into
    /// a circular arc of radius λ/κ towards the patch's side: the centre
    /// at height y is (λ/κ)(1 − cos κy, 0, sin κy) for X = 0.
    #[test]
    fn a_patch_along_the_whole_rod_makes_an_arc() {
        let rod = PatchRod {
            curvature: 0.02,
            twist: 0.0,
            phase: 0.0,
            stretch: -0.5,
        };
        let placed = [Placed {
            patch: patch(0.0, 50.0, 100.0),
            rod,
        }];
        let heights: Vec<f64> = (1..=400).map(|k| k as f64 * 0.25).collect();
        let c = centres(3.0, 100.0, &uniform(3.5), &placed, &heights);
        let (lambda, kappa) = (3.0, 0.02);
        for (y, p) in heights.iter().zip(&c) {
            let exact =
                Point::new(1.0 - (kappa * y).cos(), 0.0, (kappa * y).sin()) * (lambda / kappa);
            // Each step's chord is (κ dy)²/24 of it short of the arc:
            // 1e-6 here, under 1e-3 mm over the rod.
            assert!((p - exact).norm() < 1e-3, "y {y}: {p:?} against {exact:?}");
        }
    }

    /// A patch's side turned round the tube by X/R₀ turns its bend with it.
    #[test]
    fn a_patch_round_the_tube_bends_towards_its_side() {
        let rod = PatchRod {
            curvature: 0.05,
            twist: 0.0,
            phase: 0.0,
            stretch: 0.0,
        };
        let radius = 3.0;
        let x_mm = radius * std::f64::consts::FRAC_PI_2;
        let placed = [Placed {
            patch: patch(x_mm, 30.0, 20.0),
            rod,
        }];
        let many: Vec<f64> = (1..=600).map(|k| k as f64 * 0.1).collect();
        let tip_fine = *centres(radius, 60.0, &uniform(3.0), &placed, &many)
            .last()
            .unwrap();
        assert!(tip_fine.x.abs() < 1e-9 && tip_fine.y > 10.0, "{tip_fine:?}");
    }
}
