//! Constant-strain membrane triangle.
//!
//! Reference triangle in its own plane with orthonormal axes (e₁ along the hoop
//! direction, e₂ = n × e₁), linear shape functions Nₐ with constant gradients
//! ∇Nₐ. Deformed positions xₐ give the two convected tangents
//! F₁ = Σ xₐ ∂Nₐ/∂ξ₁, F₂ = Σ xₐ ∂Nₐ/∂ξ₂ and C = [[F₁·F₁, F₁·F₂], [F₁·F₂, F₂·F₂]].
//!
//! Energy  Π_e = A₀ ψ(C), ψ = Σ_layers t W(C) (or a cut element's laminate,
//!         [`Section::response`]).
//! Force   fₐ = A₀ Σₖ gₖ ∂cₖ/∂xₐ with ∂c₁₁/∂xₐ = 2Nₐ,₁F₁, ∂c₂₂/∂xₐ = 2Nₐ,₂F₂,
//!         ∂c₁₂/∂xₐ = Nₐ,₁F₂ + Nₐ,₂F₁ (g = ∂ψ/∂c).
//! Tangent Kₐᵦ = A₀ [Σₖₗ Hₖₗ ∂cₖ/∂xₐ ⊗ ∂cₗ/∂xᵦ
//!               + (2g₁₁Nₐ,₁Nᵦ,₁ + 2g₂₂Nₐ,₂Nᵦ,₂ + g₁₂(Nₐ,₁Nᵦ,₂ + Nₐ,₂Nᵦ,₁)) I].

use nalgebra::{Matrix3, SMatrix};

use super::section::Section;
use crate::curve::Point;
use crate::material::Material;

/// Geometry of a reference triangle, computed once.
#[derive(Debug, Clone)]
pub struct Triangle {
    pub nodes: [usize; 3],
    pub area: f64,
    /// ∇Nₐ in the local frame: `grad[a] = [∂Nₐ/∂ξ₁, ∂Nₐ/∂ξ₂]`.
    pub grad: [[f64; 2]; 3],
}

impl Triangle {
    /// `hoop` is the hoop direction near the triangle (its projection onto the
    /// triangle's plane becomes ξ₁).
    pub fn new(nodes: [usize; 3], x: [Point; 3], hoop: Point) -> Triangle {
        let normal = (x[1] - x[0]).cross(&(x[2] - x[0])).normalize();
        let e1 = (hoop - normal * normal.dot(&hoop)).normalize();
        let e2 = normal.cross(&e1);
        let local: Vec<[f64; 2]> = x
            .iter()
            .map(|p| [(p - x[0]).dot(&e1), (p - x[0]).dot(&e2)])
            .collect();
        let [(x0, y0), (x1, y1), (x2, y2)] = [0, 1, 2].map(|a| (local[a][0], local[a][1]));
        let twice = (x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0);
        let grad = [
            [(y1 - y2) / twice, (x2 - x1) / twice],
            [(y2 - y0) / twice, (x0 - x2) / twice],
            [(y0 - y1) / twice, (x1 - x0) / twice],
        ];
        Triangle {
            nodes,
            area: 0.5 * twice,
            grad,
        }
    }

    /// Convected tangents F₁, F₂ at deformed positions `x`.
    pub fn tangents(&self, x: &[Point; 3]) -> (Point, Point) {
        let mut f1 = Point::zeros();
        let mut f2 = Point::zeros();
        for (xa, grad) in x.iter().zip(&self.grad) {
            f1 += xa * grad[0];
            f2 += xa * grad[1];
        }
        (f1, f2)
    }

    /// C = FᵀF as (c₁₁, c₂₂, c₁₂).
    pub fn cauchy_green(&self, x: &[Point; 3]) -> [f64; 3] {
        let (f1, f2) = self.tangents(x);
        [f1.dot(&f1), f2.dot(&f2), f1.dot(&f2)]
    }

    /// Energy only; +∞ when any layer is outside its domain.
    pub fn energy(&self, x: &[Point; 3], section: &Section, materials: &[Material]) -> f64 {
        self.area * section.energy(self.cauchy_green(x), materials)
    }

    /// Energy, nodal forces (3×3: node a's force is column a) and the 9×9
    /// tangent. `None` when outside the material domain.
    pub fn evaluate(
        &self,
        x: &[Point; 3],
        section: &Section,
        materials: &[Material],
    ) -> Option<(f64, Matrix3<f64>, SMatrix<f64, 9, 9>)> {
        let (f1, f2) = self.tangents(x);
        let c = [f1.dot(&f1), f2.dot(&f2), f1.dot(&f2)];
        let r = section.response(c, materials)?;
        let (w, g, h) = (r.energy, r.gradient, r.hessian);
        let n = &self.grad;
        // dc[a][k] = ∂cₖ/∂xₐ.
        let dc: [[Point; 3]; 3] = [0, 1, 2].map(|a| {
            [
                2.0 * n[a][0] * f1,
                2.0 * n[a][1] * f2,
                n[a][0] * f2 + n[a][1] * f1,
            ]
        });
        let mut force = Matrix3::zeros();
        let mut k = SMatrix::<f64, 9, 9>::zeros();
        // hc[a][q] = Σₚ Hₚq ∂cₚ/∂xₐ, so the material block is Σ_q hc[a][q] ⊗ ∂c_q/∂xᵦ.
        let hc: [[Point; 3]; 3] = [0, 1, 2].map(|a| {
            [0, 1, 2].map(|q| dc[a][0] * h[0][q] + dc[a][1] * h[1][q] + dc[a][2] * h[2][q])
        });
        for a in 0..3 {
            let fa = self.area * (g[0] * dc[a][0] + g[1] * dc[a][1] + g[2] * dc[a][2]);
            force.set_column(a, &fa);
            for b in 0..=a {
                let mut block = hc[a][0] * dc[b][0].transpose()
                    + hc[a][1] * dc[b][1].transpose()
                    + hc[a][2] * dc[b][2].transpose();
                let geometric = 2.0 * g[0] * n[a][0] * n[b][0]
                    + 2.0 * g[1] * n[a][1] * n[b][1]
                    + g[2] * (n[a][0] * n[b][1] + n[a][1] * n[b][0]);
                block += Matrix3::identity() * geometric;
                block *= self.area;
                k.fixed_view_mut::<3, 3>(3 * a, 3 * b).copy_from(&block);
                if b != a {
                    k.fixed_view_mut::<3, 3>(3 * b, 3 * a)
                        .copy_from(&block.transpose());
                }
            }
        }
        Some((self.area * w, force, k))
    }
}
