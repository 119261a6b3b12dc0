//! Patches of a finished design that sit on a fabrication limit.
//!
//! A design pinned at a limit says the target wants what the bounds forbid:
//! a gentle arc, for one, bends less than the narrowest allowed patch makes
//! it bend (on the reference balloon a full-length 1 mm patch gives
//! κ ≈ 0.020 mm⁻¹; a 60 mm radius needs 0.017, about a 0.85 mm patch), so
//! the design ends at `w_min_mm` with a shape error well above what the
//! model can do. The report lists such patches so that the user knows why,
//! and which bound to relax if the fabrication allows it.

use serde::{Deserialize, Serialize};

use super::variables::VariableBounds;
use crate::design::Patch;

/// A value counts as on its limit within this fraction of its range
/// (0.01 mm of the default 1–3 mm widths).
const ON_LIMIT: f64 = 5e-3;

/// One patch value on (or beyond) a fabrication limit.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AtLimit {
    /// Patch number as in the tables: 1 for P1.
    pub patch: usize,
    /// The patch's field: `h_mm`, `w_mm` or `theta_deg`.
    pub field: String,
    pub value: f64,
    /// The limit it sits on: `bounds.h_min_mm`, …, `bounds.theta_limit_deg`.
    pub bound: String,
    pub limit: f64,
    /// Past the limit, not on it: the search widens a range to hold a seed
    /// outside it (KSA's patch lengths are not bounded).
    pub beyond: bool,
}

/// Every size or angle of `patches` within `ON_LIMIT` of its range's end,
/// or beyond it, in patch order.
pub fn at_limits(patches: &[Patch], bounds: &VariableBounds) -> Vec<AtLimit> {
    let theta = bounds.theta_limit_deg;
    let ranges = [
        (
            "h_mm",
            "h_min_mm",
            "h_max_mm",
            bounds.h_min_mm,
            bounds.h_max_mm,
        ),
        (
            "w_mm",
            "w_min_mm",
            "w_max_mm",
            bounds.w_min_mm,
            bounds.w_max_mm,
        ),
        (
            "theta_deg",
            "theta_limit_deg",
            "theta_limit_deg",
            -theta,
            theta,
        ),
    ];
    let mut found = Vec::new();
    for (index, patch) in patches.iter().enumerate() {
        let values = [patch.h_mm, patch.w_mm, patch.theta_deg];
        for ((field, low_name, high_name, low, high), value) in ranges.iter().zip(values) {
            let tolerance = share_of_range(ON_LIMIT, *low, *high);
            let hit = if value <= low + tolerance {
                Some((low_name, *low))
            } else if value >= high - tolerance {
                Some((high_name, *high))
            } else {
                None
            };
            if let Some((name, limit)) = hit {
                found.push(AtLimit {
                    patch: index + 1,
                    field: field.to_string(),
                    value,
                    bound: format!("bounds.{name}"),
                    limit,
                    beyond: value < low - tolerance || value > high + tolerance,
                });
            }
        }
    }
    found
}

/// `fraction` of the range `low..high`: how near a value must be to an
/// end of it to count as on it ([`ON_LIMIT`]) or at its weakest
/// ([`NEAR_WEAKEST`]).
fn share_of_range(fraction: f64, low: f64, high: f64) -> f64 {
    fraction * (high - low).abs()
}

/// A patch counts as at its weakest within this fraction of its height's
/// and its width's ranges above their lower limits (0.4 mm of height and
/// 0.04 mm of width with the default limits): four times [`ON_LIMIT`].
/// Whether a refine ends a train's patches exactly on their lower limits
/// or a few tenths of a millimetre above them is a matter of its last
/// steps; the thinning a weakest train calls for ([`super::layout`])
/// should not be. On the curve suite under `draft` this changes no design
/// but the hand-drawn hook with jitter's, whose train ended 0.15 and
/// 0.25 mm above the smallest height in one build and on it in another
/// (docs/studies.md, "The tangent in closed form and a tabulated start").
const NEAR_WEAKEST: f64 = 4.0 * ON_LIMIT;

/// Whether `patch` is at its weakest: its height and its width both
/// within [`NEAR_WEAKEST`] of their ranges above their lower limits (or
/// below them).
pub fn at_weakest(patch: &Patch, bounds: &VariableBounds) -> bool {
    let near = |low: f64, high: f64| low + share_of_range(NEAR_WEAKEST, low, high);
    patch.h_mm <= near(bounds.h_min_mm, bounds.h_max_mm)
        && patch.w_mm <= near(bounds.w_min_mm, bounds.w_max_mm)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn patch(h_mm: f64, w_mm: f64, theta_deg: f64) -> Patch {
        Patch {
            x_mm: 0.0,
            y_mm: 50.0,
            h_mm,
            w_mm,
            theta_deg,
        }
    }

    #[test]
    fn finds_values_on_and_beyond_the_limits_and_nothing_inside() {
        let bounds = VariableBounds::default();
        assert!(at_limits(&[patch(20.0, 2.0, 10.0)], &bounds).is_empty());
        let found = at_limits(
            &[
                patch(20.0, 1.004, 0.0),
                patch(31.0, 2.0, -79.9),
                patch(10.0, 3.0, 80.0),
            ],
            &bounds,
        );
        let summary: Vec<(usize, &str, &str)> = found
            .iter()
            .map(|a| (a.patch, a.field.as_str(), a.bound.as_str()))
            .collect();
        assert_eq!(
            summary,
            [
                (1, "w_mm", "bounds.w_min_mm"),
                (2, "h_mm", "bounds.h_max_mm"),
                (2, "theta_deg", "bounds.theta_limit_deg"),
                (3, "h_mm", "bounds.h_min_mm"),
                (3, "w_mm", "bounds.w_max_mm"),
                (3, "theta_deg", "bounds.theta_limit_deg"),
            ]
        );
        assert_eq!(found[0].limit, 1.0);
        assert_eq!(found[2].limit, -80.0);
        let beyond: Vec<bool> = found.iter().map(|a| a.beyond).collect();
        assert_eq!(beyond, [false, true, false, false, false, false]);
    }

    /// A patch is at its weakest with its height and width both within
    /// 2 % of their ranges above their lower limits (0.4 mm and 0.04 mm of
    /// the default 10–30 mm and 1–3 mm), as a refine's last steps leave a
    /// train; either one further up, or a patch wider than the width
    /// allows, is not.
    #[test]
    fn at_weakest_within_two_percent_of_both_ranges() {
        let bounds = VariableBounds::default();
        assert!(at_weakest(&patch(10.0, 1.0, 0.0), &bounds));
        assert!(at_weakest(&patch(10.25, 1.03, 0.0), &bounds));
        assert!(at_weakest(&patch(9.0, 0.8, 0.0), &bounds));
        assert!(!at_weakest(&patch(10.45, 1.0, 0.0), &bounds));
        assert!(!at_weakest(&patch(10.0, 1.05, 0.0), &bounds));
        // Not on a limit as `at_limits` judges it (0.1 mm of height), yet
        // at its weakest.
        assert!(at_limits(&[patch(10.25, 1.03, 0.0)], &bounds).is_empty());
    }
}
