//! Exact area of overlap between a mesh triangle and a patch (a rotated
//! rectangle) in the unrolled plane, across the seam X = 0 = 2πR₀.
//!
//! The triangle is clipped against the rectangle's four half-planes
//! (Sutherland–Hodgman; both shapes are convex) and the area of what remains is
//! the shoelace sum. The overlap is continuous, and piecewise smooth, in every
//! patch parameter — patches never switch elements on or off whole.

use crate::design::Patch;

type P2 = [f64; 2];

/// Area of the part of `triangle` (unrolled coordinates, mm) covered by
/// `patch`, accounting for the periodic seam at `circumference`.
pub fn overlap_area(triangle: &[P2; 3], patch: &Patch, circumference: f64) -> f64 {
    patch_cut(triangle, patch, circumference).area
}

/// How a patch cuts a triangle: the covered area and the patch outline inside
/// the triangle, summarised as an orientation.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Cut {
    pub area: f64,
    pub interface: Interface,
}

/// The pieces of patch outline inside a triangle, each of length ℓᵢ with unit
/// normal at angle αᵢ (unrolled plane), summed as `length` = Σℓᵢ and the
/// doubled-angle vector `orientation` = Σℓᵢ (cos 2αᵢ, sin 2αᵢ). Doubling the
/// angle makes a normal and its opposite the same direction, so the two long
/// sides of a strip reinforce; two perpendicular sides of equal length cancel.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Interface {
    pub length: f64,
    pub orientation: P2,
}

impl Interface {
    pub fn add(&mut self, other: &Interface) {
        self.length += other.length;
        self.orientation[0] += other.orientation[0];
        self.orientation[1] += other.orientation[1];
    }

    /// |Σℓᵢ e^{2iαᵢ}| / Σℓᵢ ∈ [0, 1]: 1 for a straight cut (one direction),
    /// 0 when the directions cancel (or there is no outline).
    pub fn coherence(&self) -> f64 {
        if self.length <= 0.0 {
            return 0.0;
        }
        (self.orientation[0].hypot(self.orientation[1]) / self.length).min(1.0)
    }

    /// The mean outline normal (unit vector, sign arbitrary).
    pub fn normal(&self) -> P2 {
        let half = 0.5 * self.orientation[1].atan2(self.orientation[0]);
        [half.cos(), half.sin()]
    }
}

/// [`overlap_area`] together with the patch outline inside the triangle: the
/// edges of the clipped polygon that lie on one of the patch's sides.
pub fn patch_cut(triangle: &[P2; 3], patch: &Patch, circumference: f64) -> Cut {
    let (sin, cos) = patch.theta().sin_cos();
    // Long axis makes angle Θ with the balloon axis (Y): u = (sin Θ, cos Θ).
    let u = [sin, cos];
    let v = [cos, -sin];
    let (hh, hw) = (0.5 * patch.h_mm, 0.5 * patch.w_mm);
    let scale = triangle
        .iter()
        .map(|p| p[0].abs().max(p[1].abs()))
        .fold(circumference, f64::max);
    let on_line = 1e-9 * scale;
    // The patch and its images one circumference either side.
    let mut cut = Cut::default();
    for shift in [-circumference, 0.0, circumference] {
        let centre = [patch.x_mm + shift, patch.y_mm];
        if !bounding_boxes_meet(triangle, centre, u, v, hh, hw) {
            continue;
        }
        let mut polygon: Vec<P2> = triangle.to_vec();
        let mut sides = Vec::with_capacity(4);
        for (axis, half) in [(u, hh), (v, hw)] {
            for sign in [1.0, -1.0] {
                // Keep points with sign·(p − centre)·axis ≤ half.
                let normal = [sign * axis[0], sign * axis[1]];
                let offset = half + normal[0] * centre[0] + normal[1] * centre[1];
                polygon = clip(&polygon, normal, offset);
                if polygon.is_empty() {
                    break;
                }
                sides.push((normal, offset));
            }
        }
        cut.area += area(&polygon);
        for (normal, offset) in sides {
            let distance = |p: &P2| (normal[0] * p[0] + normal[1] * p[1] - offset).abs();
            for i in 0..polygon.len() {
                let (a, b) = (polygon[i], polygon[(i + 1) % polygon.len()]);
                if distance(&a) <= on_line && distance(&b) <= on_line {
                    let length = (b[0] - a[0]).hypot(b[1] - a[1]);
                    let doubled = 2.0 * normal[1].atan2(normal[0]);
                    cut.interface.add(&Interface {
                        length,
                        orientation: [length * doubled.cos(), length * doubled.sin()],
                    });
                }
            }
        }
    }
    cut
}

fn bounding_boxes_meet(tri: &[P2; 3], centre: P2, u: P2, v: P2, hh: f64, hw: f64) -> bool {
    let ex = hh * u[0].abs() + hw * v[0].abs();
    let ey = hh * u[1].abs() + hw * v[1].abs();
    let (min_x, max_x) = tri
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), p| (a.min(p[0]), b.max(p[0])));
    let (min_y, max_y) = tri
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), p| (a.min(p[1]), b.max(p[1])));
    max_x >= centre[0] - ex
        && min_x <= centre[0] + ex
        && max_y >= centre[1] - ey
        && min_y <= centre[1] + ey
}

/// Clips a convex polygon to the half-plane n·p ≤ offset (one
/// Sutherland–Hodgman pass).
pub(crate) fn clip(polygon: &[P2], n: P2, offset: f64) -> Vec<P2> {
    let inside = |p: &P2| n[0] * p[0] + n[1] * p[1] - offset;
    let mut out = Vec::with_capacity(polygon.len() + 1);
    for i in 0..polygon.len() {
        let (a, b) = (polygon[i], polygon[(i + 1) % polygon.len()]);
        let (da, db) = (inside(&a), inside(&b));
        if da <= 0.0 {
            out.push(a);
        }
        if (da < 0.0 && db > 0.0) || (da > 0.0 && db < 0.0) {
            let t = da / (da - db);
            out.push([a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]);
        }
    }
    out
}

/// Area of a simple polygon (shoelace; 0 for fewer than three corners).
pub(crate) fn area(polygon: &[P2]) -> f64 {
    let n = polygon.len();
    if n < 3 {
        return 0.0;
    }
    let twice: f64 = (0..n)
        .map(|i| {
            let (a, b) = (polygon[i], polygon[(i + 1) % n]);
            a[0] * b[1] - b[0] * a[1]
        })
        .sum();
    0.5 * twice.abs()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn patch(x: f64, y: f64, h: f64, w: f64, theta_deg: f64) -> Patch {
        Patch {
            x_mm: x,
            y_mm: y,
            h_mm: h,
            w_mm: w,
            theta_deg,
        }
    }

    #[test]
    fn triangle_inside_patch_is_fully_covered() {
        let tri = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
        assert!(
            (overlap_area(&tri, &patch(0.5, 0.5, 10.0, 10.0, 30.0), 100.0) - 0.5).abs() < 1e-12
        );
    }

    #[test]
    fn half_covered_square_split_into_triangles() {
        // Unit square as two triangles; a patch covering x < 0.5 exactly.
        let t1 = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]];
        let t2 = [[0.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        let p = patch(0.0, 0.5, 1.0, 1.0, 0.0);
        let a = overlap_area(&t1, &p, 100.0) + overlap_area(&t2, &p, 100.0);
        assert!((a - 0.5).abs() < 1e-12);
    }

    #[test]
    fn rotated_patch_area_is_conserved_over_a_fine_grid() {
        // Sum of overlaps over a grid covering the patch = H·W, at any angle and
        // across the seam.
        let circumference = 20.0;
        for (x, theta) in [(10.0, 0.0), (0.3, 37.0), (19.9, -71.0), (5.0, 90.0)] {
            let p = patch(x, 15.0, 8.0, 2.5, theta);
            let n = 40;
            let h = circumference / n as f64;
            let mut total = 0.0;
            for i in 0..n {
                for j in 0..n * 2 {
                    let (x0, y0) = (i as f64 * h, j as f64 * h);
                    let t1 = [[x0, y0], [x0 + h, y0], [x0 + h, y0 + h]];
                    let t2 = [[x0, y0], [x0 + h, y0 + h], [x0, y0 + h]];
                    total +=
                        overlap_area(&t1, &p, circumference) + overlap_area(&t2, &p, circumference);
                }
            }
            assert!((total - 20.0).abs() < 1e-9, "x {x} Θ {theta}: {total}");
        }
    }

    #[test]
    fn straight_cut_has_one_direction() {
        // Unit square's lower triangle, cut by the patch's side x = 0.5.
        let tri = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]];
        let cut = patch_cut(&tri, &patch(0.0, 0.5, 10.0, 1.0, 0.0), 100.0);
        assert!((cut.area - 0.125).abs() < 1e-12);
        assert!((cut.interface.length - 0.5).abs() < 1e-12);
        assert!((cut.interface.coherence() - 1.0).abs() < 1e-12);
        assert!((cut.interface.normal()[0].abs() - 1.0).abs() < 1e-12);
    }

    #[test]
    fn oblique_strip_through_a_triangle_keeps_its_direction() {
        // A 30° strip narrower than the triangle: both long sides cross it, with
        // opposite normals that must not cancel.
        let tri = [[-5.0, -5.0], [5.0, -5.0], [0.0, 5.0]];
        let cut = patch_cut(&tri, &patch(0.0, 0.0, 40.0, 1.0, 30.0), 100.0);
        assert!((cut.interface.coherence() - 1.0).abs() < 1e-12);
        let n = cut.interface.normal();
        // Long axis u = (sin 30°, cos 30°); the sides' normal is ⊥ u.
        assert!((n[0] * 0.5 + n[1] * 0.75f64.sqrt()).abs() < 1e-12);
    }

    #[test]
    fn square_corner_cancels_its_directions() {
        // The patch's corner (0, 0) sits on the triangle's symmetry line y = x:
        // two perpendicular sides of equal length (2) inside.
        let tri = [[-4.0, -4.0], [2.0, -1.0], [-1.0, 2.0]];
        let cut = patch_cut(&tri, &patch(-5.0, -5.0, 10.0, 10.0, 0.0), 100.0);
        assert!((cut.interface.length - 4.0).abs() < 1e-12);
        assert!(cut.interface.coherence() < 1e-12);
    }

    #[test]
    fn overlap_moves_continuously() {
        let tri = [[0.0, 0.0], [2.0, 0.0], [0.0, 2.0]];
        let mut last = overlap_area(&tri, &patch(-1.0, 1.0, 2.0, 2.0, 20.0), 100.0);
        for step in 1..400 {
            let x = -1.0 + step as f64 * 0.01;
            let a = overlap_area(&tri, &patch(x, 1.0, 2.0, 2.0, 20.0), 100.0);
            assert!((a - last).abs() < 0.03, "jump at x = {x}");
            last = a;
        }
    }
}
