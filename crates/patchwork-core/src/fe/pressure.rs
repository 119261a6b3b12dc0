//! Pressure as a conservative follower load: the potential −P·V(x), with V the
//! volume enclosed by the surface (divergence theorem, origin on the clamped
//! base plane, whose flat disc then contributes nothing):
//!
//!   V = Σ_triangles (1/6) x₀·(x₁ × x₂)
//!   ∂V/∂x₀ = (x₁ × x₂)/6 (cyclically), ∂²V/∂x₀∂x₁ = −[x₂]ₓ/6, ∂²V/∂x₀∂x₂ = [x₁]ₓ/6 …
//!
//! where [v]ₓ is the cross-product matrix. The Hessian is symmetric, so the
//! total potential's tangent is symmetric too.

use nalgebra::{Matrix3, SMatrix};

use crate::curve::Point;

/// Signed volume contribution of one outward-oriented triangle.
pub fn volume(x: &[Point; 3]) -> f64 {
    x[0].dot(&x[1].cross(&x[2])) / 6.0
}

/// ∂V/∂xₐ as columns.
pub fn volume_gradient(x: &[Point; 3]) -> Matrix3<f64> {
    let mut g = Matrix3::zeros();
    g.set_column(0, &(x[1].cross(&x[2]) / 6.0));
    g.set_column(1, &(x[2].cross(&x[0]) / 6.0));
    g.set_column(2, &(x[0].cross(&x[1]) / 6.0));
    g
}

/// ∂²V/∂x∂x (9×9, node-major).
pub fn volume_hessian(x: &[Point; 3]) -> SMatrix<f64, 9, 9> {
    let mut h = SMatrix::<f64, 9, 9>::zeros();
    // Block (a, b) for b = a+1 is −[x_c]ₓ/6 where c is the third node; (a, b) for
    // b = a+2 is +[x_c]ₓ/6; diagonal blocks vanish.
    for a in 0..3 {
        let b = (a + 1) % 3;
        let c = (a + 2) % 3;
        let block = -x[c].cross_matrix() / 6.0;
        h.fixed_view_mut::<3, 3>(3 * a, 3 * b).copy_from(&block);
        h.fixed_view_mut::<3, 3>(3 * b, 3 * a)
            .copy_from(&block.transpose());
    }
    h
}
