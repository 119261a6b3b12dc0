//! The fidelity presets as a data table: what each one fixes of the expert
//! [`Tuning`]. A new preset is a new row (and a name in [`Fidelity`]). The
//! time and error each costs are measured in BENCHMARKS.md.
//!
//! Every preset shares draft's search (200 evaluations on 3 mm rings with a
//! 2 mm cross-section, stopping after 80 without improvement) and its
//! refine: Levenberg–Marquardt on the graded 1 mm verification model,
//! corrected by a graded 0.5 mm model that also verifies its result.
//! Standard and fine add a final refine on the uniform 0.5 mm mesh, which
//! then verifies: standard with 15 solves, fine until it converges or 180.

use std::str::FromStr;

use serde::{Deserialize, Serialize};

use super::tuning::{FinalRefineSettings, Tuning};
use crate::fe::mesh::MeshSpec;
use crate::fe::newton::NewtonOptions;

#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Fidelity {
    /// Search on 3 mm rings, refine on graded 1 mm corrected by graded
    /// 0.5 mm, verify on graded 0.5 mm: a quick look.
    Draft,
    /// Draft's run, then a short final refine on the uniform 0.5 mm mesh
    /// (the rest of 75 solves), which also verifies.
    #[default]
    Standard,
    /// Draft's run, then a final refine on the uniform 0.5 mm mesh until it
    /// converges or the rest of 240 solves is spent, which also verifies.
    Fine,
}

/// A mesh whose cross-section may be set apart from its element size: the
/// nodes around follow from the balloon's radius, so a row is independent of
/// the balloon.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeshRow {
    pub element_mm: f64,
    /// Edge length around the cross-section; none: `element_mm`.
    pub section_mm: Option<f64>,
    /// Axial element length along bare stretches; none: uniform.
    pub straight_mm: Option<f64>,
}

impl MeshRow {
    /// The mesh for a balloon of radius `radius_mm`.
    pub fn mesh(&self, radius_mm: f64) -> MeshSpec {
        MeshSpec {
            element_mm: self.element_mm,
            around: self
                .section_mm
                .map(|section| MeshSpec::around_for(radius_mm, section)),
            straight_mm: self.straight_mm,
        }
    }
}

/// One preset: the values it fixes. Everything else in [`Tuning`] is the
/// default.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PresetRow {
    pub fidelity: Fidelity,
    pub search_budget: usize,
    pub search_patience: usize,
    pub search_mesh: MeshRow,
    pub verify_mesh: MeshRow,
    /// Solves of the refine, the final refine's included.
    pub refine_budget: usize,
    /// The shape error (%) at or below which the refines stop.
    pub refine_tolerance: f64,
    pub correction_mesh: Option<MeshRow>,
    /// The final refine's mesh; it starts after the refine has spent at most
    /// `FINAL_REFINE_STAGING` solves.
    pub final_refine_mesh: Option<MeshRow>,
    /// Designs of the spread's Monte-Carlo check (0: none).
    pub monte_carlo: usize,
    /// The model the spread finds each patch's sources on.
    pub spread_patch_mesh: MeshRow,
}

/// The search model: 3 mm rings with the 2 mm cross-section (10 sides on the
/// reference balloon) and 6 mm bare stretches. A 1 mm section is more
/// accurate but makes each factorisation about 5× dearer, which no search
/// can afford (the final refine pays it).
const SEARCH_MESH: MeshRow = MeshRow {
    element_mm: 3.0,
    section_mm: Some(2.0),
    straight_mm: Some(6.0),
};
const GRADED_1MM: MeshRow = MeshRow {
    element_mm: 1.0,
    section_mm: None,
    straight_mm: Some(4.0),
};
/// The spread's model for the patches' sources: a patch's change on it
/// lies within 6 % of the verification model's (the largest ones of six
/// draft designs), at about a fifth of the cost (docs/studies.md, "The
/// spread's solves").
const GRADED_2MM: MeshRow = MeshRow {
    element_mm: 2.0,
    section_mm: None,
    straight_mm: Some(6.0),
};
const GRADED_HALF_MM: MeshRow = MeshRow {
    element_mm: 0.5,
    section_mm: None,
    straight_mm: Some(4.0),
};
const UNIFORM_HALF_MM: MeshRow = MeshRow {
    element_mm: 0.5,
    section_mm: None,
    straight_mm: None,
};

/// Draft's and standard's refine tolerance: 0.1 % of the target's length.
/// The graded 0.5 mm model that verifies their designs (the correction's,
/// `MeshSpec::default_simulation`; not the graded 1 mm `verify_mesh` the
/// refine solves on) lies 0.02–0.07 % of the length from a converged
/// uniform 0.25 mm solution on four designs, so a refine below this
/// follows the mesh's error more than the balloon's shape; on the Hilbert
/// curve the last 0.02–0.04 points cost two thirds of the refine's solves
/// (docs/studies.md, "The refine tolerance"). Fine refines on until its
/// steps stop paying.
pub const REFINE_TOLERANCE: f64 = 0.1;

/// Solves the refine on the verification model may spend before a final
/// refine takes over (draft's whole refine budget).
pub const FINAL_REFINE_STAGING: usize = 60;

/// Fine's Monte-Carlo check of the spread: 200 designs, the sampled RMS
/// within about 5 % (1/√(2N)) of its expectation where the changes are
/// normal-like (the check states its own error from its draws).
pub const FINE_MONTE_CARLO: usize = 200;

/// The presets. Patience: on the Hilbert curve and the pancake the search
/// never beats the KSA seed (80 evaluations instead of 200, same design); on
/// the spring its improvements come at 49, 65 and 97 evaluations. No preset
/// runs the CMA-ES polish: on ten round trips a 60-solve refine beat a
/// 120-evaluation polish (median 0.06 % against 0.28 %) in a quarter of the
/// time (`round_trips -- refine=60` against `round_trips -- polish=120
/// refine=0`).
pub const PRESETS: [PresetRow; 3] = [
    PresetRow {
        fidelity: Fidelity::Draft,
        search_budget: 200,
        search_patience: 80,
        search_mesh: SEARCH_MESH,
        verify_mesh: GRADED_1MM,
        refine_budget: 60,
        refine_tolerance: REFINE_TOLERANCE,
        correction_mesh: Some(GRADED_HALF_MM),
        final_refine_mesh: None,
        monte_carlo: 0,
        spread_patch_mesh: GRADED_2MM,
    },
    PresetRow {
        fidelity: Fidelity::Standard,
        search_budget: 200,
        search_patience: 80,
        search_mesh: SEARCH_MESH,
        verify_mesh: GRADED_1MM,
        refine_budget: 75,
        refine_tolerance: REFINE_TOLERANCE,
        correction_mesh: Some(GRADED_HALF_MM),
        final_refine_mesh: Some(UNIFORM_HALF_MM),
        monte_carlo: 0,
        spread_patch_mesh: GRADED_2MM,
    },
    PresetRow {
        fidelity: Fidelity::Fine,
        search_budget: 200,
        search_patience: 80,
        search_mesh: SEARCH_MESH,
        verify_mesh: GRADED_1MM,
        refine_budget: 240,
        refine_tolerance: 0.0,
        correction_mesh: Some(GRADED_HALF_MM),
        final_refine_mesh: Some(UNIFORM_HALF_MM),
        monte_carlo: FINE_MONTE_CARLO,
        spread_patch_mesh: GRADED_2MM,
    },
];

impl Fidelity {
    pub const NAMES: [&'static str; 3] = ["draft", "standard", "fine"];

    /// This preset's row of [`PRESETS`].
    pub fn row(self) -> &'static PresetRow {
        PRESETS
            .iter()
            .find(|row| row.fidelity == self)
            .unwrap_or(&PRESETS[1])
    }

    /// The tuning this preset fixes, for a balloon of radius `radius_mm`.
    pub fn tuning(self, radius_mm: f64) -> Tuning {
        let row = self.row();
        Tuning {
            search_budget: row.search_budget,
            search_patience: row.search_patience,
            search_mesh: row.search_mesh.mesh(radius_mm),
            verify_mesh: row.verify_mesh.mesh(radius_mm),
            refine_budget: row.refine_budget,
            refine_tolerance: row.refine_tolerance,
            correction_mesh: row.correction_mesh.map(|m| m.mesh(radius_mm)),
            final_refine: row.final_refine_mesh.map(|m| FinalRefineSettings {
                mesh: m.mesh(radius_mm),
                staging_solves: FINAL_REFINE_STAGING,
                newton: NewtonOptions::default(),
            }),
            trains: true,
            gentle_bends: true,
            planar_designs: true,
            spread: true,
            spread_patch_mesh: Some(row.spread_patch_mesh.mesh(radius_mm)),
            monte_carlo: row.monte_carlo,
            ..Tuning::default()
        }
    }

    /// The search's default evaluations (the preset's).
    pub fn budget(self) -> usize {
        self.row().search_budget
    }

    /// The refine's solves, the final refine's included (the preset's).
    pub fn refine_budget(self) -> usize {
        self.row().refine_budget
    }
}

impl FromStr for Fidelity {
    type Err = String;

    fn from_str(text: &str) -> Result<Self, Self::Err> {
        match text {
            "draft" => Ok(Fidelity::Draft),
            "standard" => Ok(Fidelity::Standard),
            "fine" => Ok(Fidelity::Fine),
            _ => Err(format!(
                "unknown fidelity {text:?}: choose one of {}",
                Fidelity::NAMES.join(", ")
            )),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_fidelity_has_exactly_one_row() {
        for name in Fidelity::NAMES {
            let fidelity: Fidelity = name.parse().unwrap();
            assert_eq!(PRESETS.iter().filter(|r| r.fidelity == fidelity).count(), 1);
        }
    }

    #[test]
    fn the_reference_balloons_search_section_has_ten_sides() {
        let tuning = Fidelity::Draft.tuning(3.18);
        assert_eq!(tuning.search_mesh.around, Some(10));
        assert_eq!(tuning.verify_mesh, MeshSpec::graded(1.0, 4.0));
        assert_eq!(tuning.correction_mesh, Some(MeshSpec::graded(0.5, 4.0)));
        assert!(tuning.final_refine.is_none());
        let fine = Fidelity::Fine.tuning(3.18).final_refine.unwrap();
        assert_eq!(fine.mesh, MeshSpec::uniform(0.5));
        assert_eq!(fine.staging_solves, Fidelity::Draft.refine_budget());
    }

    /// Draft and standard refine to 0.1 % of the length; fine until its
    /// steps stop paying.
    #[test]
    fn fine_alone_refines_past_the_tolerance() {
        let tolerance = |f: Fidelity| f.tuning(3.18).refine_tolerance;
        assert_eq!(tolerance(Fidelity::Draft), REFINE_TOLERANCE);
        assert_eq!(tolerance(Fidelity::Standard), REFINE_TOLERANCE);
        assert_eq!(tolerance(Fidelity::Fine), 0.0);
    }
}
