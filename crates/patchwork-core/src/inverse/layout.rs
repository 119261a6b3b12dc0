//! Other layouts than KSA's: patches added where the target bends more
//! gently than KSA's curvature tolerance marks, and what each tried layout
//! reached.
//!
//! KSA marks the samples whose curvature is above `kappa_tol`; a bend
//! gentler than that all along (an arc of radius 150 mm against 0.01 mm⁻¹)
//! gets no patch, and a lower tolerance everywhere adds patches to stretches
//! that are straight but for sampling noise. So the finer layout is tried
//! after the refine, as a candidate: KSA at a `FINER` fraction of the
//! tolerance, its patches that fall where the design has none added to the
//! design, their circumferential positions brought into the design's frame
//! (KSA measures X from its own first patch) by the patches the two
//! layouts share. The candidate is refined like the design, and kept only
//! if its verified shape error is lower.

use std::f64::consts::TAU;

use serde::{Deserialize, Serialize};

use crate::curve::Curve;
use crate::design::{Design, Patch};
use crate::ksa::{KsaParams, Stretch, ksa};

/// The finer layout's curvature tolerance, as a fraction of the run's.
pub const FINER: f64 = 0.4;

/// Space kept between an added patch and the design's own (mm).
const CLEARANCE_MM: f64 = 1.0;

/// A layout the run tried, and what it reached.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LayoutTrial {
    /// What the layout is, in words.
    pub layout: String,
    pub patches: usize,
    /// Its verified shape error after its refine (% of length).
    pub shape_error_percent: f64,
    /// Whether the design is this layout's.
    pub chosen: bool,
}

/// The design with the finer layout's patches added where it has none, or
/// none when the finer layout adds nothing.
pub fn with_gentle_bends(
    design: &Design,
    target: &Curve,
    kappa_tol: f64,
    params: &KsaParams,
) -> Option<Design> {
    let finer = KsaParams {
        kappa_tol: FINER * kappa_tol,
        l0_mm: design.balloon.length_mm,
        r0_mm: design.balloon.radius_mm,
        stretch: Stretch::Fixed(target.length() / design.balloon.length_mm),
        ..params.clone()
    };
    let candidates = ksa(target, &finer).ok()?.patches;
    let circumference = TAU * design.balloon.radius_mm;
    let offset = frame_offset(&design.patches, &candidates, circumference);
    let added: Vec<Patch> = candidates
        .iter()
        .filter(|c| !design.patches.iter().any(|p| overlap(p, c)))
        .map(|c| Patch {
            x_mm: (c.x_mm + offset).rem_euclid(circumference),
            ..*c
        })
        .collect();
    if added.is_empty() {
        return None;
    }
    let mut patches = design.patches.clone();
    patches.extend(added);
    patches.sort_by(|a, b| a.y_mm.total_cmp(&b.y_mm));
    Some(Design {
        patches,
        ..design.clone()
    })
}

/// Whether two patches' axial spans come within `CLEARANCE_MM`.
fn overlap(a: &Patch, b: &Patch) -> bool {
    (a.y_mm - b.y_mm).abs() < 0.5 * (a.h_mm + b.h_mm) + CLEARANCE_MM
}

/// The circumferential shift taking KSA's frame to the design's: the
/// circular mean of X(design) − X(KSA) over the pairs of patches that
/// overlap; 0 when none do (a design without patches has no frame yet).
fn frame_offset(design: &[Patch], candidates: &[Patch], circumference: f64) -> f64 {
    let (mut sin, mut cos) = (0.0, 0.0);
    for p in design {
        for c in candidates.iter().filter(|c| overlap(p, c)) {
            let angle = TAU * (p.x_mm - c.x_mm) / circumference;
            sin += angle.sin();
            cos += angle.cos();
        }
    }
    match sin == 0.0 && cos == 0.0 {
        true => 0.0,
        false => sin.atan2(cos) / TAU * circumference,
    }
}

#[cfg(test)]
#[path = "layout_tests.rs"]
mod tests;
