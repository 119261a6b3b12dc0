//! Design validation: every field checked once, at the boundary, the error
//! naming the field as a JSON path (`patches[2].h_mm`).

use super::{Design, Patch};
use crate::material::MaterialError;

#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{field}: {reason}")]
pub struct DesignError {
    /// JSON path of the offending field.
    pub field: String,
    pub reason: String,
}

fn error(field: impl Into<String>, reason: impl Into<String>) -> DesignError {
    DesignError {
        field: field.into(),
        reason: reason.into(),
    }
}

/// The largest length or position a design may state, mm: a kilometre,
/// beyond any balloon, and small enough that sums on the mesh keep
/// sub-micrometre precision.
pub const MAX_MM: f64 = 1e6;

fn positive(field: &str, value: f64) -> Result<(), DesignError> {
    if value.is_finite() && value > 0.0 && value <= MAX_MM {
        Ok(())
    } else {
        Err(error(
            field,
            format!("must be a positive number of at most {MAX_MM:e} mm, got {value}"),
        ))
    }
}

fn position(field: &str, value: f64) -> Result<(), DesignError> {
    match value.is_finite() && value.abs() <= MAX_MM {
        true => Ok(()),
        false => Err(error(
            field,
            format!("must be within ±{MAX_MM:e} mm, got {value}"),
        )),
    }
}

fn material(path: &str, e: MaterialError) -> DesignError {
    error(
        format!("{path}.{}", e.field),
        format!("{} (model {})", e.reason, e.model),
    )
}

impl Design {
    /// Checks every field. Patches must have finite positive sizes, a finite
    /// angle within ±90°, and overlap the balloon's tube (a patch may hang off an
    /// end — the part off the balloon is ignored — but not lie wholly off it).
    pub fn validate(&self) -> Result<(), DesignError> {
        let b = &self.balloon;
        positive("balloon.length_mm", b.length_mm)?;
        positive("balloon.radius_mm", b.radius_mm)?;
        positive("balloon.wall_mm", b.wall_mm)?;
        if b.wall_mm >= b.radius_mm {
            return Err(error(
                "balloon.wall_mm",
                "must be smaller than balloon.radius_mm (a membrane)",
            ));
        }
        b.material
            .validate()
            .map_err(|e| material("balloon.material", e))?;
        positive("patch.thickness_mm", self.patch.thickness_mm)?;
        self.patch
            .material
            .validate()
            .map_err(|e| material("patch.material", e))?;
        if !(self.pressure_kpa.is_finite() && self.pressure_kpa >= 0.0) {
            return Err(error(
                "pressure_kpa",
                format!("must be finite and ≥ 0, got {}", self.pressure_kpa),
            ));
        }
        if self.patches.len() > 200 {
            return Err(error(
                "patches",
                format!("at most 200 patches, got {}", self.patches.len()),
            ));
        }
        for (i, p) in self.patches.iter().enumerate() {
            validate_patch(i, p, b.length_mm)?;
        }
        Ok(())
    }
}

fn validate_patch(i: usize, p: &Patch, length: f64) -> Result<(), DesignError> {
    let field = |name: &str| format!("patches[{i}].{name}");
    position(&field("x_mm"), p.x_mm)?;
    position(&field("y_mm"), p.y_mm)?;
    positive(&field("h_mm"), p.h_mm)?;
    positive(&field("w_mm"), p.w_mm)?;
    if !(p.theta_deg.is_finite() && p.theta_deg.abs() <= 90.0) {
        return Err(error(
            field("theta_deg"),
            format!("must be within ±90°, got {}", p.theta_deg),
        ));
    }
    let half = p.axial_half_extent();
    if p.y_mm + half <= 0.0 || p.y_mm - half >= length {
        return Err(error(
            field("y_mm"),
            format!(
                "patch lies entirely off the balloon (axial extent {:.2}..{:.2} mm, balloon 0..{length} mm)",
                p.y_mm - half,
                p.y_mm + half
            ),
        ));
    }
    Ok(())
}
