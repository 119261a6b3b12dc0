//! Planar designs for planar targets. A patch at Θ = 0 is symmetric about
//! the plane through the balloon's axis and its own centre line, so it
//! bends the tube in that plane and twists it not at all; patches at Θ = 0
//! on one line of the tube (X₀) and the line opposite (X₀ + πR₀) bend it
//! one way or the other within one plane. A planar target gets such a
//! design: its patches are put there and the search and refines keep X and
//! Θ fixed.

use crate::design::Patch;

/// `patches` at Θ = 0, each moved round the tube to the nearer of the first
/// patch's line and the line opposite (`circumference` = 2πR₀).
pub fn flattened(patches: &[Patch], circumference: f64) -> Vec<Patch> {
    let Some(first) = patches.first() else {
        return vec![];
    };
    let line = first.x_mm.rem_euclid(circumference);
    let opposite = (line + 0.5 * circumference).rem_euclid(circumference);
    patches
        .iter()
        .map(|p| {
            let off = (p.x_mm - line).rem_euclid(circumference) / circumference;
            let x_mm = match (0.25..0.75).contains(&off) {
                true => opposite,
                false => line,
            };
            Patch {
                x_mm,
                theta_deg: 0.0,
                ..*p
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn patch(x_mm: f64, theta_deg: f64) -> Patch {
        Patch {
            x_mm,
            y_mm: 20.0,
            h_mm: 15.0,
            w_mm: 2.0,
            theta_deg,
        }
    }

    #[test]
    fn patches_go_to_the_first_line_or_its_opposite_at_zero_angle() {
        let c = 20.0;
        let flat = flattened(
            &[
                patch(3.0, 4.0),
                patch(7.0, -2.0),
                patch(14.5, 0.0),
                patch(19.0, 9.0),
            ],
            c,
        );
        let xs: Vec<f64> = flat.iter().map(|p| p.x_mm).collect();
        // 7 is 4 mm (a fifth of the way round) from 3: same line; 14.5 is
        // 11.5 mm round: opposite; 19 is 4 mm the other way: same line.
        assert_eq!(xs, vec![3.0, 3.0, 13.0, 3.0]);
        assert!(flat.iter().all(|p| p.theta_deg == 0.0));
        assert!(flat.iter().all(|p| p.h_mm == 15.0 && p.w_mm == 2.0));
        assert!(flattened(&[], c).is_empty());
    }
}
