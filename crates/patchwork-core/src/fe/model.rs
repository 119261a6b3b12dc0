//! The assembled finite-element model of one design: mesh, per-element sections
//! (wall and patch shares from exact overlap areas; cut elements as laminates
//! along the patch outline), degrees of freedom and the total potential
//! Π(x) = Σ_e A₀ ψ_e(C) − P V(x) (ψ = Σ t W for an uncut element) with its
//! gradient and Hessian.

use super::element::Triangle;
use super::laminate::Layer;
use super::mesh::TubeMesh;
use super::overlap::{Interface, patch_cut};
use super::pressure::{facet_load_factor, volume, volume_gradient};
use super::section::{Cover, CutElements, Section, WALL, materials};
use crate::curve::Point;
use crate::design::Design;
use crate::material::Material;

/// The model of one design on one mesh.
#[derive(Debug, Clone)]
pub struct Model {
    pub mesh: TubeMesh,
    pub triangles: Vec<Triangle>,
    /// Final section of each triangle.
    pub sections: Vec<Section>,
    /// How patches cover each triangle (for sections at other stiffnesses).
    covers: Vec<Cover>,
    cut_elements: CutElements,
    pub materials: Vec<Material>,
    /// First DOF of each node, `None` for clamped nodes.
    pub dof: Vec<Option<usize>>,
    pub dof_count: usize,
    /// The inflation pressure (MPa).
    pub pressure: f64,
    /// What the facets are loaded with per unit of pressure
    /// ([`facet_load_factor`] of the mesh's section).
    pub load_factor: f64,
    /// Where each triangle's tangent entries start in the pattern's order
    /// (`assembly.rs`), the total last.
    pub(super) value_offsets: Vec<usize>,
    /// Threads an assembly splits the triangles over ([`Model::with_threads`]).
    pub(super) threads: usize,
}

impl Model {
    pub fn new(design: &Design, mesh: TubeMesh, cut_elements: CutElements) -> Model {
        let triangles: Vec<Triangle> = mesh
            .triangles
            .iter()
            .map(|&nodes| {
                let x = nodes.map(|n| mesh.nodes[n]);
                let centroid = (x[0] + x[1] + x[2]) / 3.0;
                let hoop = Point::new(-centroid.y, centroid.x, 0.0);
                let hoop = if hoop.norm() > 1e-12 {
                    hoop
                } else {
                    Point::x()
                };
                Triangle::new(nodes, x, hoop)
            })
            .collect();
        let circumference = mesh.circumference();
        let covers: Vec<Cover> = triangles
            .iter()
            .enumerate()
            .map(|(t, tri)| {
                if t >= mesh.tube_triangles {
                    return Cover::BARE;
                }
                let corners = unrolled_triangle(&mesh, tri.nodes);
                let mut area = 0.0;
                let mut interface = Interface::default();
                for patch in &design.patches {
                    let cut = patch_cut(&corners, patch, circumference);
                    area += cut.area;
                    interface.add(&cut.interface);
                }
                Cover {
                    share: area / flat_area(&corners),
                    normal: local_normal(tri, &corners, interface.normal()),
                    coherence: interface.coherence(),
                }
            })
            .collect();
        let materials = materials(design);
        let sections = covers
            .iter()
            .map(|cover| Section::new(cover, 1.0, design, cut_elements, &materials))
            .collect();
        let mut dof = vec![None; mesh.nodes.len()];
        let mut next = 0;
        for (node, fixed) in mesh.fixed.iter().enumerate() {
            if !fixed {
                dof[node] = Some(next);
                next += 3;
            }
        }
        let load_factor = facet_load_factor(mesh.around);
        let mut model = Model {
            mesh,
            triangles,
            sections,
            covers,
            cut_elements,
            materials,
            dof,
            dof_count: next,
            pressure: design.pressure_mpa(),
            load_factor,
            value_offsets: Vec::new(),
            threads: 1,
        };
        model.value_offsets = model.entry_offsets();
        model
    }

    /// This model assembling on up to `threads` threads: the same potential,
    /// gradient and tangent to the last bit, in less wall time where cores
    /// are idle (a solve that runs alone).
    pub fn with_threads(mut self, threads: usize) -> Model {
        self.threads = threads.max(1);
        self
    }

    /// Sections with patch stiffness scaled by `s` ∈ [0, 1] (continuation).
    pub fn sections_at(&self, design: &Design, s: f64) -> Vec<Section> {
        if s >= 1.0 {
            return self.sections.clone();
        }
        if s <= 0.0 {
            let wall = Layer {
                material: WALL,
                thickness: design.balloon.wall_mm,
            };
            return vec![Section::uniform(vec![wall]); self.covers.len()];
        }
        self.covers
            .iter()
            .map(|cover| Section::new(cover, s, design, self.cut_elements, &self.materials))
            .collect()
    }

    /// Share of each triangle covered by patches (summed over patches, so
    /// above 1 where they overlap).
    pub fn patch_share(&self) -> Vec<f64> {
        self.covers.iter().map(|c| c.share).collect()
    }

    /// Positions of all nodes from the reference positions and a DOF vector.
    pub fn positions(&self, u: &[f64]) -> Vec<Point> {
        self.mesh
            .nodes
            .iter()
            .zip(&self.dof)
            .map(|(x, d)| match d {
                Some(i) => Point::new(u[*i], u[i + 1], u[i + 2]),
                None => *x,
            })
            .collect()
    }

    /// Each node's move under a change `du` of the DOFs (zero where clamped).
    pub fn moves(&self, du: &[f64]) -> Vec<Point> {
        (self.dof.iter())
            .map(|d| d.map_or(Point::zeros(), |i| Point::new(du[i], du[i + 1], du[i + 2])))
            .collect()
    }

    /// DOF vector from node positions.
    pub fn unknowns(&self, x: &[Point]) -> Vec<f64> {
        let mut u = vec![0.0; self.dof_count];
        for (node, d) in self.dof.iter().enumerate() {
            if let Some(i) = d {
                u[*i..*i + 3].copy_from_slice(x[node].as_slice());
            }
        }
        u
    }

    pub(super) fn corners(&self, x: &[Point], t: usize) -> [Point; 3] {
        self.triangles[t].nodes.map(|n| x[n])
    }

    /// The pressure load on the facets (MPa): the pressure times
    /// [`Model::load_factor`].
    pub fn load(&self) -> f64 {
        self.pressure * self.load_factor
    }

    /// Enclosed volume (mm³).
    pub fn volume(&self, x: &[Point]) -> f64 {
        (0..self.triangles.len())
            .map(|t| volume(&self.corners(x, t)))
            .sum()
    }

    /// ∂V/∂u over the free DOFs.
    pub fn volume_gradient(&self, x: &[Point]) -> Vec<f64> {
        let mut g = vec![0.0; self.dof_count];
        for (t, tri) in self.triangles.iter().enumerate() {
            let dv = volume_gradient(&self.corners(x, t));
            for a in 0..3 {
                if let Some(d) = self.dof[tri.nodes[a]] {
                    for i in 0..3 {
                        g[d + i] += dv[(i, a)];
                    }
                }
            }
        }
        g
    }
}

impl Model {
    /// ∇Π of this model at `x` minus `base`'s at the same positions: the
    /// out-of-balance force that changing `base`'s design (or the balloon's
    /// reference length) to this model's puts on a state of `base`. Both
    /// models must number their nodes and DOFs alike (`None` otherwise, or
    /// outside a material's domain). Where they share the reference mesh
    /// and pressure, only the triangles whose section differs contribute,
    /// so moving one patch costs the elements its outline touches.
    pub fn gradient_change(&self, base: &Model, x: &[Point]) -> Option<Vec<f64>> {
        if self.dof != base.dof || self.triangles.len() != base.triangles.len() {
            return None;
        }
        let shared = self.mesh.nodes == base.mesh.nodes
            && self.load() == base.load()
            && self.materials == base.materials;
        let mut change = vec![0.0; self.dof_count];
        for t in 0..self.triangles.len() {
            if shared && self.sections[t] == base.sections[t] {
                continue;
            }
            let corners = self.corners(x, t);
            let dv = volume_gradient(&corners);
            for (model, sign) in [(self, 1.0), (base, -1.0)] {
                let tri = &model.triangles[t];
                let (_, force, _) = tri.evaluate(&corners, &model.sections[t], &model.materials)?;
                for a in 0..3 {
                    if let Some(d) = self.dof[tri.nodes[a]] {
                        for i in 0..3 {
                            change[d + i] += sign * (force[(i, a)] - model.load() * dv[(i, a)]);
                        }
                    }
                }
            }
        }
        Some(change)
    }
}

/// A normal given in the unrolled plane, in the triangle's local frame. The
/// affine map from unrolled to local coordinates, M = L U⁻¹ (edge vectors),
/// takes normals by M⁻ᵀ = L⁻ᵀ Uᵀ, and L⁻ᵀ's columns are ∇N₁, ∇N₂.
fn local_normal(tri: &Triangle, corners: &[[f64; 2]; 3], normal: [f64; 2]) -> [f64; 2] {
    let mut n = [0.0; 2];
    for a in 1..3 {
        let along = (corners[a][0] - corners[0][0]) * normal[0]
            + (corners[a][1] - corners[0][1]) * normal[1];
        n[0] += along * tri.grad[a][0];
        n[1] += along * tri.grad[a][1];
    }
    let norm = n[0].hypot(n[1]);
    if norm > 0.0 {
        [n[0] / norm, n[1] / norm]
    } else {
        [1.0, 0.0]
    }
}

/// Unrolled corners of a tube triangle, unwrapped across the seam so the
/// triangle is not split in two.
fn unrolled_triangle(mesh: &TubeMesh, nodes: [usize; 3]) -> [[f64; 2]; 3] {
    let c = mesh.circumference();
    let mut p = nodes.map(|n| mesh.unrolled(n));
    let max_x = p.iter().map(|q| q[0]).fold(f64::MIN, f64::max);
    for q in &mut p {
        if max_x - q[0] > 0.5 * c {
            q[0] += c;
        }
    }
    p
}

fn flat_area(p: &[[f64; 2]; 3]) -> f64 {
    0.5 * ((p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[2][0] - p[0][0]) * (p[1][1] - p[0][1]))
        .abs()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fe::mesh::MeshSpec;
    use crate::fe::{SimulateOptions, simulate};

    /// Skipping the triangles whose section did not change loses nothing:
    /// the change equals the difference of two full assemblies; and a model
    /// numbered differently has none.
    #[test]
    fn the_gradient_change_is_the_difference_of_two_assemblies() {
        let design = Design::one_patch_test_scene();
        let mut other = design.clone();
        other.patches[0].theta_deg = 13.0;
        other.patches[0].h_mm = 16.0;
        let spec = MeshSpec::uniform(2.0);
        let options = SimulateOptions {
            mesh: spec,
            ..SimulateOptions::default()
        };
        let x = simulate(&design, &options).unwrap().positions;
        let model =
            |d: &Design, spec| Model::new(d, TubeMesh::for_design(d, spec), CutElements::default());
        let (base, changed) = (model(&design, spec), model(&other, spec));
        let gradient = |m: &Model| {
            let mut g = vec![0.0; m.dof_count];
            m.assemble(&x, &m.sections, 0.0, &mut g, &mut Vec::new())
                .unwrap();
            g
        };
        let (g0, g1) = (gradient(&base), gradient(&changed));
        let change = changed.gradient_change(&base, &x).unwrap();
        let size = g1.iter().fold(0.0_f64, |m, g| m.max(g.abs()));
        let worst = change
            .iter()
            .zip(g1.iter().zip(&g0))
            .fold(0.0_f64, |m, (c, (a, b))| m.max((c - (a - b)).abs()));
        assert!(
            size > 1e-3 && worst < 1e-12 * size.max(1.0),
            "{worst} against {size}"
        );
        let finer = model(&other, MeshSpec::uniform(1.0));
        assert!(finer.gradient_change(&base, &x).is_none());
    }
}
