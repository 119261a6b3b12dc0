//! The sources of spread: each patch's five quantities and the three of the
//! whole balloon; each names itself and moves a design by its tolerance.

use serde::{Deserialize, Serialize};

use super::tolerances::Tolerances;
use crate::calibrate::{Materials, Parameter};
use crate::design::Design;

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PatchQuantity {
    X,
    Y,
    Angle,
    Length,
    Width,
}

/// One source of spread.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(tag = "source", rename_all = "snake_case")]
pub enum Source {
    /// Patch `patch` (from 1, as the design's files number them).
    Patch {
        patch: usize,
        quantity: PatchQuantity,
    },
    Pressure,
    Wall,
    Modulus,
}

/// A patch's sources: X, Y, angle, length, width.
pub const SOURCES_PER_PATCH: usize = 5;

impl Source {
    /// Every source of `design` whose tolerance is not 0.
    pub fn all(design: &Design, t: &Tolerances) -> Vec<Source> {
        let quantities: [(PatchQuantity, f64); SOURCES_PER_PATCH] = [
            (PatchQuantity::X, t.placement_mm),
            (PatchQuantity::Y, t.placement_mm),
            (PatchQuantity::Angle, t.angle_deg),
            (PatchQuantity::Length, t.size_mm),
            (PatchQuantity::Width, t.size_mm),
        ];
        let patches = (1..=design.patches.len()).flat_map(|patch| {
            quantities
                .iter()
                .filter(|(_, tol)| *tol > 0.0)
                .map(move |&(quantity, _)| Source::Patch { patch, quantity })
        });
        let balloon = [
            (Source::Pressure, t.pressure_kpa),
            (Source::Wall, t.wall_percent),
            (Source::Modulus, t.modulus_percent),
        ]
        .into_iter()
        .filter(|(_, tol)| *tol > 0.0)
        .map(|(s, _)| s);
        patches.chain(balloon).collect()
    }

    /// Whether `design` has a patch source under `t` (a patch, and a
    /// placement, angle or size tolerance above 0): whether a model for
    /// the patches' sources is worth solving.
    pub fn any_patch(design: &Design, t: &Tolerances) -> bool {
        let all = Source::all(design, t);
        all.iter().any(|s| matches!(s, Source::Patch { .. }))
    }

    /// Two of `sources` that act as one, where both are there: the wall's
    /// thickness and the balloon's modulus. The membrane's energy per unit
    /// of reference area is t·W, and the modulus scales W (its bulk term
    /// with it), so a wall (1 + ε) times thicker and a modulus (1 + ε)
    /// times stiffer give the same state (to round-off: `spread::tests`).
    /// The one with the smaller tolerance, the other, and the ratio of
    /// their tolerances (at most 1).
    pub fn equivalent(sources: &[Source], t: &Tolerances) -> Option<(usize, usize, f64)> {
        let at = |s: Source| sources.iter().position(|&k| k == s);
        let (wall, modulus) = (at(Source::Wall)?, at(Source::Modulus)?);
        Some(match t.modulus_percent <= t.wall_percent {
            true => (modulus, wall, t.modulus_percent / t.wall_percent),
            false => (wall, modulus, t.wall_percent / t.modulus_percent),
        })
    }

    /// Its tolerance and the unit it is in.
    pub fn tolerance(self, t: &Tolerances) -> (f64, &'static str) {
        match self {
            Source::Patch { quantity, .. } => match quantity {
                PatchQuantity::X | PatchQuantity::Y => (t.placement_mm, "mm"),
                PatchQuantity::Angle => (t.angle_deg, "°"),
                PatchQuantity::Length | PatchQuantity::Width => (t.size_mm, "mm"),
            },
            Source::Pressure => (t.pressure_kpa, "kPa"),
            Source::Wall => (t.wall_percent, "%"),
            Source::Modulus => (t.modulus_percent, "%"),
        }
    }

    /// As a person reads it: "P3 angle", "pressure".
    pub fn label(self) -> String {
        match self {
            Source::Patch { patch, quantity } => {
                let q = match quantity {
                    PatchQuantity::X => "X (around)",
                    PatchQuantity::Y => "Y (along)",
                    PatchQuantity::Angle => "angle",
                    PatchQuantity::Length => "length",
                    PatchQuantity::Width => "width",
                };
                format!("P{patch} {q}")
            }
            Source::Pressure => "pressure".into(),
            Source::Wall => "wall thickness".into(),
            Source::Modulus => "balloon modulus".into(),
        }
    }

    /// `design` with this source moved by `by` (its unit's).
    pub fn moved(self, design: &Design, by: f64) -> Design {
        let mut d = design.clone();
        match self {
            Source::Patch { patch, quantity } => {
                let p = &mut d.patches[patch - 1];
                match quantity {
                    PatchQuantity::X => p.x_mm += by,
                    PatchQuantity::Y => p.y_mm += by,
                    PatchQuantity::Angle => p.theta_deg += by,
                    PatchQuantity::Length => p.h_mm += by,
                    PatchQuantity::Width => p.w_mm += by,
                }
            }
            Source::Pressure => d.pressure_kpa += by,
            Source::Wall => d.balloon.wall_mm *= 1.0 + by / 100.0,
            Source::Modulus => {
                let materials = Materials {
                    balloon: d.balloon.material.clone(),
                    patch: d.patch.material.clone(),
                };
                let modulus = Parameter::Modulus.value(&materials).unwrap_or(1.0);
                let scaled = Parameter::Modulus.with(&materials, modulus * (1.0 + by / 100.0));
                d = scaled.on(&d);
            }
        }
        d
    }
}
