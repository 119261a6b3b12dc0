//! The tolerances a lab works to, with defaults for hand-glued patches and
//! a hand-set regulator; each is one standard deviation.

use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Tolerances {
    /// A patch's placement around the balloon (X) and along it (Y), mm.
    pub placement_mm: f64,
    /// A patch's angle, degrees.
    pub angle_deg: f64,
    /// A patch's length and width as cut, mm.
    pub size_mm: f64,
    /// The inflation pressure, kPa.
    pub pressure_kpa: f64,
    /// The balloon's wall thickness, % of its own.
    pub wall_percent: f64,
    /// The balloon material's modulus, % of its own.
    pub modulus_percent: f64,
}

impl Default for Tolerances {
    fn default() -> Self {
        Tolerances {
            placement_mm: 1.0,
            angle_deg: 2.0,
            size_mm: 0.2,
            pressure_kpa: 0.5,
            wall_percent: 5.0,
            modulus_percent: 3.0,
        }
    }
}

impl Tolerances {
    /// Every tolerance finite and 0 or more (0: that source left out); the
    /// error names the field.
    pub fn validate(&self) -> Result<(), String> {
        self.check()
            .map_err(|(field, reason)| format!("{field} {reason}"))
    }

    /// As [`validate`](Self::validate), the field apart from the reason.
    pub fn check(&self) -> Result<(), (&'static str, String)> {
        for (field, value, most) in [
            ("placement_mm", self.placement_mm, 50.0),
            ("angle_deg", self.angle_deg, 45.0),
            ("size_mm", self.size_mm, 20.0),
            ("pressure_kpa", self.pressure_kpa, 20.0),
            ("wall_percent", self.wall_percent, 50.0),
            ("modulus_percent", self.modulus_percent, 50.0),
        ] {
            if !(value.is_finite() && (0.0..=most).contains(&value)) {
                return Err((field, format!("must be between 0 and {most}, got {value}")));
            }
        }
        Ok(())
    }
}
