use serde::{Deserialize, Serialize};

/// One strain-limiting patch on the *uninflated* balloon, in the unrolled
/// rectangle `[0, 2πR₀) × [0, L₀]` (JSON field names are the public contract).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Patch {
    /// Circumferential arc position of the centre (mm), wraps at 2πR₀.
    pub x_mm: f64,
    /// Axial position of the centre from the clamped base (mm).
    pub y_mm: f64,
    /// Length along the patch's long axis (mm).
    pub h_mm: f64,
    /// Width (mm).
    pub w_mm: f64,
    /// Angle of the long axis from the balloon axis (degrees; radians inside).
    pub theta_deg: f64,
}

impl Patch {
    /// Θ in radians.
    pub fn theta(&self) -> f64 {
        self.theta_deg.to_radians()
    }

    /// Half the axial extent of the rotated rectangle (mm):
    /// (H·|cos Θ| + W·|sin Θ|)/2.
    pub fn axial_half_extent(&self) -> f64 {
        let (s, c) = self.theta().sin_cos();
        0.5 * (self.h_mm * c.abs() + self.w_mm * s.abs())
    }
}
