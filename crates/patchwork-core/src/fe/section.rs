//! What each element is made of: its layers (wall, patch), and for an element
//! that a patch outline cuts, the two phases as a laminate.
//!
//! A cut element's energy blends the laminate and the area average by the
//! coherence c of the outline inside it (see [`super::overlap::Interface`]):
//!
//!   ψ = c ψ_laminate + (1 − c) ψ_average.
//!
//! c = 1 for a straight cut (one side of a patch, or both long sides of a
//! narrow strip), falling to 0 where two perpendicular sides of a corner
//! cancel — there a single laminate direction means nothing. The blend keeps
//! the energy continuous as a patch moves and turns: c, the share and the
//! normal all move continuously except the normal where c = 0, which then has
//! no weight.

use super::laminate::{Laminate, Layer};
use crate::design::{Bonding, Design};
use crate::material::{Material, Response};

pub const WALL: usize = 0;
pub const PATCH: usize = 1;

/// How elements that a patch outline cuts are modelled. In JSON (the API's
/// `cut_elements`) and on the command line: `laminate` or `average`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum CutElements {
    /// Rank-one laminate of the covered and bare phases, oriented along the
    /// patch outline ([`super::laminate`]).
    #[default]
    #[serde(rename = "laminate")]
    Laminate,
    /// Area-weighted average of the phases' energies (Voigt).
    #[serde(rename = "average")]
    AreaAverage,
}

/// The material of one element.
#[derive(Debug, Clone, PartialEq)]
pub struct Section {
    /// The area-averaged layers: the whole element when it is not cut.
    pub layers: Vec<Layer>,
    /// The cut element's laminate and its weight c ∈ (0, 1].
    pub laminate: Option<(Laminate, f64)>,
}

/// Where and how patches cover one element.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cover {
    /// Covered area over element area, summed over patches (may exceed 1
    /// where patches overlap).
    pub share: f64,
    /// Mean outline normal in the triangle's local frame, and its coherence.
    pub normal: [f64; 2],
    pub coherence: f64,
}

impl Cover {
    /// No patch on the element.
    pub const BARE: Cover = Cover {
        share: 0.0,
        normal: [1.0, 0.0],
        coherence: 0.0,
    };
}

impl std::str::FromStr for CutElements {
    type Err = String;

    /// `laminate` or `average` (the command line's spelling): the names are
    /// the serde ones, kept in one place.
    fn from_str(name: &str) -> Result<Self, Self::Err> {
        serde_json::from_value(serde_json::Value::from(name))
            .map_err(|_| format!("cut elements: `laminate` or `average`, not `{name}`"))
    }
}

impl Section {
    /// The section of an element with cover `cover`, patch stiffness scaled by
    /// `s` ∈ [0, 1] (continuation from the bare tube); `materials` as
    /// [`materials`] orders them.
    pub fn new(
        cover: &Cover,
        s: f64,
        design: &Design,
        rule: CutElements,
        materials: &[Material],
    ) -> Section {
        let (share, covered, bare) = phases(cover.share, s, design);
        let layers = average(share, &covered, &bare);
        let cut = share > 1e-12 && share < 1.0 - 1e-12 && cover.coherence > 0.0;
        let laminate = (cut && rule == CutElements::Laminate).then(|| {
            let laminate = Laminate::new(share, cover.normal, covered, bare, materials);
            (laminate, cover.coherence)
        });
        Section { layers, laminate }
    }

    /// ψ(C) per unit reference area and its derivatives in (c₁₁, c₂₂, c₁₂);
    /// `None` outside a material's domain.
    pub fn response(&self, c: [f64; 3], materials: &[Material]) -> Option<Response> {
        let average = layers_response(&self.layers, c, materials)?;
        let Some((laminate, weight)) = &self.laminate else {
            return Some(average);
        };
        let cut = laminate.response(c, materials)?;
        let blend = |a: f64, b: f64| weight * a + (1.0 - weight) * b;
        Some(Response {
            energy: blend(cut.energy, average.energy),
            gradient: [0, 1, 2].map(|i| blend(cut.gradient[i], average.gradient[i])),
            hessian: [0, 1, 2]
                .map(|i| [0, 1, 2].map(|j| blend(cut.hessian[i][j], average.hessian[i][j]))),
        })
    }

    /// ψ(C) only; +∞ outside a material's domain.
    pub fn energy(&self, c: [f64; 3], materials: &[Material]) -> f64 {
        let average: f64 = self
            .layers
            .iter()
            .map(|l| l.thickness * materials[l.material].energy(c))
            .sum();
        match &self.laminate {
            None => average,
            Some(_) if !average.is_finite() => f64::INFINITY,
            Some((laminate, weight)) => {
                weight * laminate.energy(c, materials) + (1.0 - weight) * average
            }
        }
    }

    /// A copy whose laminate starts each minimisation from the jump its
    /// previous one found ([`Laminate::remembering`]): for one solve's own use.
    pub fn remembering(&self) -> Section {
        Section {
            layers: self.layers.clone(),
            laminate: (self.laminate.as_ref()).map(|(l, weight)| (l.remembering(), *weight)),
        }
    }

    /// A uniform section (one stack of layers, no cut).
    pub fn uniform(layers: Vec<Layer>) -> Section {
        Section {
            layers,
            laminate: None,
        }
    }
}

/// The materials a [`Layer`] refers to, indexed by [`WALL`] and [`PATCH`].
pub fn materials(design: &Design) -> Vec<Material> {
    vec![
        design.balloon.material.clone(),
        design.patch.material.clone(),
    ]
}

/// Σ t W(C) over a stack of layers, with derivatives.
pub fn layers_response(layers: &[Layer], c: [f64; 3], materials: &[Material]) -> Option<Response> {
    let mut sum = Response {
        energy: 0.0,
        gradient: [0.0; 3],
        hessian: [[0.0; 3]; 3],
    };
    for layer in layers {
        let r = materials[layer.material].response(c);
        if !r.is_admissible() {
            return None;
        }
        let t = layer.thickness;
        sum.energy += t * r.energy;
        for i in 0..3 {
            sum.gradient[i] += t * r.gradient[i];
            for j in 0..3 {
                sum.hessian[i][j] += t * r.hessian[i][j];
            }
        }
    }
    Some(sum)
}

/// The covered share φ ∈ [0, 1] and the layers of the covered and bare phases.
/// `replace`: the patch takes the wall's place (overlapping patches cannot
/// remove more than all of it); `laminate`: the patch lies on the wall, and
/// where patches overlap inside the element their thicknesses add.
fn phases(share: f64, s: f64, design: &Design) -> (f64, Vec<Layer>, Vec<Layer>) {
    let wall = design.balloon.wall_mm;
    let patch = design.patch.thickness_mm;
    let phi = share.clamp(0.0, 1.0);
    let layer = |material, thickness| Layer {
        material,
        thickness,
    };
    let covered = match design.patch.bonding {
        Bonding::Replace => vec![layer(WALL, wall * (1.0 - s)), layer(PATCH, patch * s)],
        Bonding::Laminate => {
            let stacked = if phi > 0.0 { share / phi } else { 1.0 };
            vec![layer(WALL, wall), layer(PATCH, patch * s * stacked)]
        }
    };
    let covered = covered.into_iter().filter(|l| l.thickness > 0.0).collect();
    (phi, covered, vec![layer(WALL, wall)])
}

/// φ·covered + (1 − φ)·bare as one stack (same-material layers merged).
fn average(phi: f64, covered: &[Layer], bare: &[Layer]) -> Vec<Layer> {
    let mut out: Vec<Layer> = Vec::new();
    let weighted = covered
        .iter()
        .map(|l| (l, phi))
        .chain(bare.iter().map(|l| (l, 1.0 - phi)));
    for (l, w) in weighted {
        let thickness = l.thickness * w;
        if thickness <= 0.0 {
            continue;
        }
        match out.iter_mut().find(|o| o.material == l.material) {
            Some(o) => o.thickness += thickness,
            None => out.push(Layer {
                material: l.material,
                thickness,
            }),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cover(share: f64) -> Cover {
        Cover {
            share,
            normal: [1.0, 0.0],
            coherence: 1.0,
        }
    }

    fn thickness(layers: &[Layer], material: usize) -> f64 {
        layers
            .iter()
            .filter(|l| l.material == material)
            .map(|l| l.thickness)
            .sum()
    }

    #[test]
    fn average_layers_are_the_area_weighted_stack() {
        let d = Design::reference(vec![]);
        let (t, p) = (d.balloon.wall_mm, d.patch.thickness_mm);
        let s = Section::new(&cover(0.25), 1.0, &d, CutElements::Laminate, &materials(&d));
        assert!((thickness(&s.layers, WALL) - 0.75 * t).abs() < 1e-15);
        assert!((thickness(&s.layers, PATCH) - 0.25 * p).abs() < 1e-15);
        assert!(s.laminate.is_some());
        // Half-way through continuation: the covered phase is half wall, half patch.
        let s = Section::new(&cover(0.25), 0.5, &d, CutElements::Laminate, &materials(&d));
        assert!((thickness(&s.layers, WALL) - (0.75 + 0.125) * t).abs() < 1e-15);
        assert!((thickness(&s.layers, PATCH) - 0.125 * p).abs() < 1e-15);
    }

    #[test]
    fn only_cut_elements_are_laminates() {
        let d = Design::reference(vec![]);
        for share in [0.0, 1.0, 1.4] {
            let s = Section::new(
                &cover(share),
                1.0,
                &d,
                CutElements::Laminate,
                &materials(&d),
            );
            assert!(s.laminate.is_none(), "share {share}");
        }
        let s = Section::new(
            &cover(0.5),
            1.0,
            &d,
            CutElements::AreaAverage,
            &materials(&d),
        );
        assert!(s.laminate.is_none());
    }

    #[test]
    fn laminate_bonding_stacks_overlapping_patches() {
        let mut d = Design::reference(vec![]);
        d.patch.bonding = Bonding::Laminate;
        let (t, p) = (d.balloon.wall_mm, d.patch.thickness_mm);
        let s = Section::new(&cover(1.5), 1.0, &d, CutElements::Laminate, &materials(&d));
        assert!((thickness(&s.layers, WALL) - t).abs() < 1e-15);
        assert!((thickness(&s.layers, PATCH) - 1.5 * p).abs() < 1e-15);
    }
}
