//! The design variables: each patch's X, Y, H, W, Θ, each free or fixed, with
//! bounds. CMA-ES searches the unit cube of the free variables; this module maps
//! between that cube and patches.

use serde::{Deserialize, Serialize};

use crate::design::{Design, Patch};

/// Which of a patch's parameters the optimiser may change.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Freedom {
    pub x: bool,
    pub y: bool,
    pub h: bool,
    pub w: bool,
    pub theta: bool,
}

impl Default for Freedom {
    /// Patchwork frees everything (the authors froze X and Θ).
    fn default() -> Self {
        Freedom {
            x: true,
            y: true,
            h: true,
            w: true,
            theta: true,
        }
    }
}

/// Bounds of the design variables relative to the seed and absolute
/// fabrication limits (mm, degrees).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct VariableBounds {
    /// X within ± this of the seed (mm of circumference).
    pub x_window_mm: f64,
    /// Y within ± this of the seed (the authors used 5 mm).
    pub y_window_mm: f64,
    /// Patch length limits (the authors used 10–30 mm).
    pub h_min_mm: f64,
    pub h_max_mm: f64,
    /// Patch width limits (the authors used 1–3 mm).
    pub w_min_mm: f64,
    pub w_max_mm: f64,
    /// Θ within ± this of the seed, and never beyond ±`theta_limit_deg`.
    pub theta_window_deg: f64,
    pub theta_limit_deg: f64,
}

impl Default for VariableBounds {
    fn default() -> Self {
        VariableBounds {
            x_window_mm: 5.0,
            y_window_mm: 5.0,
            h_min_mm: 10.0,
            h_max_mm: 30.0,
            w_min_mm: 1.0,
            w_max_mm: 3.0,
            theta_window_deg: 30.0,
            theta_limit_deg: 80.0,
        }
    }
}

impl VariableBounds {
    /// Checks that every bound is finite and the ranges are non-empty.
    pub fn validate(&self) -> Result<(), VariableError> {
        let b = self;
        let check = |field, ok: bool, reason: &str| {
            if ok {
                Ok(())
            } else {
                Err(VariableError {
                    field,
                    reason: reason.to_string(),
                })
            }
        };
        check(
            "x_window_mm",
            b.x_window_mm.is_finite() && b.x_window_mm > 0.0,
            "must be positive",
        )?;
        check(
            "y_window_mm",
            b.y_window_mm.is_finite() && b.y_window_mm > 0.0,
            "must be positive",
        )?;
        check(
            "h_min_mm",
            b.h_min_mm.is_finite() && b.h_min_mm > 0.0 && b.h_min_mm < b.h_max_mm,
            "must be positive and below h_max_mm",
        )?;
        check("h_max_mm", b.h_max_mm.is_finite(), "must be finite")?;
        check(
            "w_min_mm",
            b.w_min_mm.is_finite() && b.w_min_mm > 0.0 && b.w_min_mm < b.w_max_mm,
            "must be positive and below w_max_mm",
        )?;
        check("w_max_mm", b.w_max_mm.is_finite(), "must be finite")?;
        check(
            "theta_window_deg",
            b.theta_window_deg.is_finite() && b.theta_window_deg > 0.0,
            "must be positive",
        )?;
        check(
            "theta_limit_deg",
            b.theta_limit_deg.is_finite() && b.theta_limit_deg > 0.0 && b.theta_limit_deg <= 90.0,
            "must be in (0, 90]",
        )
    }
}

impl VariableBounds {
    /// These bounds with windows that span the whole balloon from a start at
    /// X = 0, Θ = 0: X around the circumference (±πR0), Y along the length,
    /// Θ across its limit. The size limits stay.
    pub fn spanning(&self, length_mm: f64, radius_mm: f64) -> VariableBounds {
        VariableBounds {
            x_window_mm: std::f64::consts::PI * radius_mm,
            y_window_mm: length_mm,
            theta_window_deg: self.theta_limit_deg,
            ..*self
        }
    }
}

impl VariableBounds {
    /// `design` with every patch's H and W clamped into these limits; none
    /// if they all are within them already.
    pub fn sizes_within(&self, design: &Design) -> Option<Design> {
        if design.patches.iter().all(|p| self.holds_size(p)) {
            return None;
        }
        Some(Design {
            patches: design.patches.iter().map(|p| self.size_within(p)).collect(),
            ..design.clone()
        })
    }

    /// Whether `patch`'s H and W are within the fabrication limits.
    pub fn holds_size(&self, patch: &Patch) -> bool {
        (self.h_min_mm..=self.h_max_mm).contains(&patch.h_mm)
            && (self.w_min_mm..=self.w_max_mm).contains(&patch.w_mm)
    }

    /// `patch` with its H and W clamped into the fabrication limits.
    pub fn size_within(&self, patch: &Patch) -> Patch {
        Patch {
            h_mm: patch.h_mm.clamp(self.h_min_mm, self.h_max_mm),
            w_mm: patch.w_mm.clamp(self.w_min_mm, self.w_max_mm),
            ..*patch
        }
    }
}

/// An impossible bound, naming the field.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("bounds.{field}: {reason}")]
pub struct VariableError {
    pub field: &'static str,
    pub reason: String,
}

/// The mapping between the unit cube of free variables and a list of patches.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DesignSpace {
    pub seed: Vec<Patch>,
    /// (patch, parameter index 0..5, lower, upper) for each free variable.
    pub free: Vec<(usize, usize, f64, f64)>,
}

impl DesignSpace {
    pub fn new(
        seed: Vec<Patch>,
        freedom: Freedom,
        bounds: &VariableBounds,
        balloon_length: f64,
    ) -> Result<DesignSpace, VariableError> {
        bounds.validate()?;
        let b = bounds;
        let mut free = Vec::new();
        for (i, p) in seed.iter().enumerate() {
            let (h_lo, h_hi) = limits(p.h_mm, b.h_min_mm, b.h_max_mm);
            let (w_lo, w_hi) = limits(p.w_mm, b.w_min_mm, b.w_max_mm);
            let ranges = [
                (freedom.x, p.x_mm - b.x_window_mm, p.x_mm + b.x_window_mm),
                (
                    freedom.y,
                    (p.y_mm - b.y_window_mm).max(0.0),
                    (p.y_mm + b.y_window_mm).min(balloon_length),
                ),
                (freedom.h, h_lo, h_hi),
                (freedom.w, w_lo, w_hi),
                (
                    freedom.theta,
                    (p.theta_deg - b.theta_window_deg).max(-b.theta_limit_deg),
                    (p.theta_deg + b.theta_window_deg).min(b.theta_limit_deg),
                ),
            ];
            for (k, (is_free, lo, hi)) in ranges.into_iter().enumerate() {
                if is_free && hi > lo {
                    free.push((i, k, lo, hi));
                }
            }
        }
        Ok(DesignSpace { seed, free })
    }

    /// The space around `seed` with its sizes first brought within the
    /// fabrication limits (H and W clamped into them), so that no point of
    /// it lies beyond a limit; [`DesignSpace::new`] instead widens a size's
    /// range to hold a seed beyond it.
    pub fn within_limits(
        seed: &[Patch],
        freedom: Freedom,
        bounds: &VariableBounds,
        balloon_length: f64,
    ) -> Result<DesignSpace, VariableError> {
        bounds.validate()?;
        let inside = seed.iter().map(|p| bounds.size_within(p)).collect();
        DesignSpace::new(inside, freedom, bounds, balloon_length)
    }

    pub fn dimension(&self) -> usize {
        self.free.len()
    }

    /// The seed in unit-cube coordinates.
    pub fn seed_point(&self) -> Vec<f64> {
        self.free
            .iter()
            .map(|&(i, k, lo, hi)| (get(&self.seed[i], k) - lo) / (hi - lo))
            .collect()
    }

    /// Patches for a point of the unit cube (coordinates outside [0, 1] are
    /// clamped; the optimiser's bound transform keeps them inside anyway).
    pub fn patches(&self, u: &[f64]) -> Vec<Patch> {
        let mut patches = self.seed.clone();
        for (&(i, k, lo, hi), &v) in self.free.iter().zip(u) {
            set(&mut patches[i], k, lo + (hi - lo) * v.clamp(0.0, 1.0));
        }
        patches
    }
}

/// The range of a size with fabrication limits `[min, max]`. A seed outside
/// them widens the range to hold it with a margin of a quarter of the limits'
/// span on both sides: a seed on the edge of the range would let CMA-ES's
/// bound transform move it one way only (on the Hilbert curve, KSA's 31 mm
/// patches against a 30 mm limit made every candidate shorter than the seed).
fn limits(seed: f64, min: f64, max: f64) -> (f64, f64) {
    if (min..=max).contains(&seed) {
        return (min, max);
    }
    let margin = 0.25 * (max - min);
    (
        min.min(seed - margin).max(0.5 * min.min(seed)),
        max.max(seed + margin),
    )
}

fn get(p: &Patch, k: usize) -> f64 {
    [p.x_mm, p.y_mm, p.h_mm, p.w_mm, p.theta_deg][k]
}

fn set(p: &mut Patch, k: usize, v: f64) {
    match k {
        0 => p.x_mm = v,
        1 => p.y_mm = v,
        2 => p.h_mm = v,
        3 => p.w_mm = v,
        _ => p.theta_deg = v,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn patch(h_mm: f64) -> Patch {
        Patch {
            x_mm: 0.0,
            y_mm: 50.0,
            h_mm,
            w_mm: 2.0,
            theta_deg: 0.0,
        }
    }

    /// (lower, upper, seed's unit coordinate) of the free H variable.
    fn h_range(h_mm: f64) -> (f64, f64, f64) {
        let space = DesignSpace::new(
            vec![patch(h_mm)],
            Freedom::default(),
            &VariableBounds::default(),
            100.0,
        )
        .unwrap();
        let k = space.free.iter().position(|f| f.1 == 2).unwrap();
        (space.free[k].2, space.free[k].3, space.seed_point()[k])
    }

    #[test]
    fn a_seed_within_the_limits_keeps_them() {
        assert_eq!(h_range(20.0), (10.0, 30.0, 0.5));
    }

    #[test]
    fn a_seed_beyond_the_limits_lies_inside_its_range_with_a_margin() {
        // KSA's Hilbert patches are 31.3 mm long against the 30 mm limit.
        let (lo, hi, u) = h_range(31.34);
        assert_eq!((lo, hi), (10.0, 36.34));
        assert!(u > 0.7 && u < 0.9, "seed at u = {u}");
        let (lo, hi, u) = h_range(4.0);
        assert_eq!((lo, hi), (2.0, 30.0));
        assert!(u > 0.0 && u < 0.2, "seed at u = {u}");
    }

    #[test]
    fn spanning_bounds_free_a_centred_patch_over_the_whole_balloon() {
        let bounds = VariableBounds::default().spanning(100.0, 3.0);
        let space =
            DesignSpace::new(vec![patch(20.0)], Freedom::default(), &bounds, 100.0).unwrap();
        let range = |k: usize| {
            let f = space.free.iter().find(|f| f.1 == k).unwrap();
            (f.2, f.3)
        };
        let half_turn = std::f64::consts::PI * 3.0;
        assert_eq!(range(0), (-half_turn, half_turn));
        assert_eq!(range(1), (0.0, 100.0));
        assert_eq!(range(2), (10.0, 30.0));
        assert_eq!(range(4), (-80.0, 80.0));
    }
}
