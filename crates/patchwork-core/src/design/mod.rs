//! The design schema shared by the CLI, the API and files. Every field except
//! `patches` defaults to the authors' reference scene (DESIGN.md).

mod patch;
pub mod random;
pub mod scenes;
mod validate;

use serde::{Deserialize, Serialize};

pub use patch::Patch;
pub use validate::DesignError;

use crate::material::{Compressibility, Material};

/// The uninflated balloon.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Balloon {
    /// Uninflated length L₀ (mm).
    pub length_mm: f64,
    /// Uninflated mid-surface radius R₀ (mm).
    pub radius_mm: f64,
    /// Wall thickness t (mm).
    pub wall_mm: f64,
    pub material: Material,
}

impl Default for Balloon {
    fn default() -> Self {
        Balloon {
            length_mm: 292.0,
            radius_mm: 3.18,
            wall_mm: 0.183,
            material: Material::reference_balloon(),
        }
    }
}

impl Balloon {
    /// 2πR₀ (mm): the width of the unrolled rectangle.
    pub fn circumference(&self) -> f64 {
        std::f64::consts::TAU * self.radius_mm
    }
}

/// How a patch joins the wall in the model.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum Bonding {
    /// The authors' section model: where the patch is, it *replaces* the wall.
    #[default]
    Replace,
    /// The patch is a second layer on top of the wall (both carry load).
    Laminate,
}

/// The patch material and thickness (all patches share them).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct PatchSpec {
    pub thickness_mm: f64,
    pub material: Material,
    pub bonding: Bonding,
}

impl Default for PatchSpec {
    fn default() -> Self {
        PatchSpec {
            thickness_mm: 0.49,
            material: Material::reference_patch(),
            bonding: Bonding::Replace,
        }
    }
}

/// A complete design: balloon, patch specification, pressure and patches.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Design {
    #[serde(default)]
    pub balloon: Balloon,
    #[serde(default)]
    pub patch: PatchSpec,
    /// Internal (gauge) pressure (kPa).
    #[serde(default = "default_pressure")]
    pub pressure_kpa: f64,
    pub patches: Vec<Patch>,
}

fn default_pressure() -> f64 {
    20.0
}

impl Design {
    /// The reference scene with the given patches.
    pub fn reference(patches: Vec<Patch>) -> Design {
        Design {
            balloon: Balloon::default(),
            patch: PatchSpec::default(),
            pressure_kpa: default_pressure(),
            patches,
        }
    }

    /// The same design with both materials' compressibility set to `c`:
    /// `Compressibility::Incompressible` for the incompressible model of the
    /// same materials.
    pub fn with_compressibility(mut self, c: Compressibility) -> Design {
        self.balloon.material.compressibility = c;
        self.patch.material.compressibility = c;
        self
    }

    /// The unit tests' small scene: an 80 mm reference balloon with one
    /// 15 × 2.5 mm patch at Y = 40 mm, turned by 10°.
    #[cfg(test)]
    pub(crate) fn one_patch_test_scene() -> Design {
        let patch = Patch {
            x_mm: 0.0,
            y_mm: 40.0,
            h_mm: 15.0,
            w_mm: 2.5,
            theta_deg: 10.0,
        };
        let mut design = Design::reference(vec![patch]);
        design.balloon.length_mm = 80.0;
        design
    }

    /// Pressure in MPa (N/mm²), the unit the mechanics works in.
    pub fn pressure_mpa(&self) -> f64 {
        self.pressure_kpa * 1e-3
    }

    /// Scales the balloon's length by `ratio`, and the patches' axial
    /// positions and lengths with it (a design's balloon length is chosen
    /// after its patches, from mechanics).
    pub fn stretch_length(&mut self, ratio: f64) {
        self.balloon.length_mm *= ratio;
        for p in &mut self.patches {
            p.y_mm *= ratio;
            p.h_mm *= ratio;
        }
    }

    /// Scales the balloon's length by `ratio` and the patches' axial
    /// positions with it, keeping the patches' sizes: a balloon cut longer
    /// or shorter with the same patches placed at the same fractions of it.
    pub fn stretch_positions(&mut self, ratio: f64) {
        self.balloon.length_mm *= ratio;
        for p in &mut self.patches {
            p.y_mm *= ratio;
        }
    }
}
