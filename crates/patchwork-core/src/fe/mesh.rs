//! The balloon's surface mesh: the tube meshed in the unrolled rectangle
//! `[0, 2πR₀) × [0, L₀]` (periodic in X) and mapped onto the cylinder, closed at
//! the far end by a hemispherical cap; the ring at Y = 0 is clamped.
//!
//! Triangles are oriented with outward normals (needed by the volume integral).
//! Quads are split along alternating diagonals so the mesh has no preferred
//! handedness — a one-way split would twist the tube by itself.

use std::f64::consts::{FRAC_PI_2, TAU};

use super::grading::{fine_zones, graded_rings};
use crate::curve::Point;
use crate::design::Design;

/// Mesh resolution.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeshSpec {
    /// Target element edge length (mm).
    pub element_mm: f64,
    /// Nodes around the circumference; `None` derives it from `element_mm`.
    /// The cross-section is a polygon of this many sides, whose flat facets
    /// the model loads with P / cos(π/n) so that a uniform tube takes the
    /// round tube's stretches ([`facet_load_factor`](super::pressure::facet_load_factor)).
    pub around: Option<usize>,
    /// Axial element length along bare stretches (mm); `None` meshes the whole
    /// tube with `element_mm`. With a value, `element_mm` applies only where
    /// patches are and at both ends (see `grading`).
    pub straight_mm: Option<f64>,
}

impl MeshSpec {
    /// The mesh a design is simulated on unless told otherwise: 0.5 mm
    /// elements under patches and at the ends, growing to 4 mm along bare
    /// stretches — the model every preset verifies a design on (its
    /// correction model), so simulating a design reproduces its predicted
    /// centreline. On the bare reference tube at 20 kPa its hoop and axial
    /// stretches are within 0.2 % of membrane theory (+0.08 % and +0.12 %,
    /// `cargo test --release --test cli simulate_defaults`; test
    /// `fe_tube_theory` for incompressible materials); a 2 mm uniform mesh
    /// within 1 % (+0.69 %, +0.95 %). A patched centreline converges more
    /// slowly with the mesh: on four designs this mesh lies 0.02–0.07 % of
    /// the length from a uniform 0.25 mm solution, a graded 1 mm one
    /// 0.08–0.46 % (docs/studies.md, "Loading the facets").
    pub const fn default_simulation() -> MeshSpec {
        MeshSpec {
            element_mm: 0.5,
            around: None,
            straight_mm: Some(4.0),
        }
    }

    /// The mesh a user's options ask for: neither given, the default
    /// ([`MeshSpec::default_simulation`]); `element_mm` alone, a uniform
    /// mesh; `straight_mm` too (or alone, with the default's element size),
    /// a graded one.
    pub fn from_options(element_mm: Option<f64>, straight_mm: Option<f64>) -> MeshSpec {
        let default = MeshSpec::default_simulation();
        match (element_mm, straight_mm) {
            (None, None) => default,
            (element_mm, straight_mm) => MeshSpec {
                straight_mm,
                ..MeshSpec::uniform(element_mm.unwrap_or(default.element_mm))
            },
        }
    }

    pub fn uniform(element_mm: f64) -> MeshSpec {
        MeshSpec {
            element_mm,
            around: None,
            straight_mm: None,
        }
    }

    /// Nodes around a circumference of radius `radius` for edges of about `h`
    /// (at least 8).
    pub fn around_for(radius: f64, h: f64) -> usize {
        ((TAU * radius / h).round() as usize).max(8)
    }

    /// `element_mm` under patches and at the ends, `straight_mm` between.
    pub fn graded(element_mm: f64, straight_mm: f64) -> MeshSpec {
        MeshSpec {
            straight_mm: Some(straight_mm),
            ..MeshSpec::uniform(element_mm)
        }
    }

    /// About how many nodes this mesh has at most on a balloon of `radius_mm`
    /// and `length_mm`, before any is built: every ring as fine as under a
    /// patch (the end caps add a few per cent).
    pub fn most_nodes(&self, radius_mm: f64, length_mm: f64) -> f64 {
        let around = self
            .around
            .unwrap_or_else(|| MeshSpec::around_for(radius_mm, self.element_mm))
            .max(8);
        around as f64 * (length_mm / self.element_mm + 2.0)
    }

    /// Whether `straight_mm` is a usable bare-stretch size for elements of
    /// `element_mm`: from the element size up to 100 times it.
    pub fn straight_fits(element_mm: f64, straight_mm: f64) -> bool {
        straight_mm.is_finite() && straight_mm >= element_mm && straight_mm <= 100.0 * element_mm
    }

    /// Checks the sizes against the balloon's radius; the message names the
    /// offending size.
    pub fn validate(&self, radius_mm: f64) -> Result<(), String> {
        let h = self.element_mm;
        if !(h.is_finite() && h > 0.0 && h <= radius_mm * 2.0) {
            return Err(format!(
                "mesh element size {h} mm must be positive and at most the balloon diameter"
            ));
        }
        if let Some(s) = self.straight_mm
            && !Self::straight_fits(h, s)
        {
            return Err(format!(
                "straight-stretch element size {s} mm must be between the element size {h} mm and 100 times it"
            ));
        }
        Ok(())
    }
}

/// "uniform 0.5 mm", "graded 0.5 mm (bare stretches 4 mm)", with ", N
/// around" when the cross-section is set apart from the element size: how
/// messages name a model.
impl std::fmt::Display for MeshSpec {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.straight_mm {
            Some(straight) => write!(
                f,
                "graded {} mm (bare stretches {straight} mm)",
                self.element_mm
            )?,
            None => write!(f, "uniform {} mm", self.element_mm)?,
        }
        match self.around {
            Some(n) => write!(f, ", {n} around"),
            None => Ok(()),
        }
    }
}

/// A surface triangle mesh of the closed-end tube.
#[derive(Debug, Clone)]
pub struct TubeMesh {
    /// Reference (uninflated) node positions (mm); z is the axis, base at z = 0.
    pub nodes: Vec<Point>,
    pub triangles: Vec<[usize; 3]>,
    /// Number of triangles belonging to the tube (the rest form the cap).
    pub tube_triangles: usize,
    /// Nodes per ring.
    pub around: usize,
    /// Axial positions of the tube's rings (mm), ring k holds nodes
    /// `k·around .. (k+1)·around`.
    pub ring_y: Vec<f64>,
    /// Clamped nodes (the base ring).
    pub fixed: Vec<bool>,
    pub radius: f64,
    pub length: f64,
}

impl TubeMesh {
    /// The mesh `spec` asks for on `design`'s balloon: uniform, or graded with
    /// fine zones around the design's patches.
    pub fn for_design(design: &Design, spec: MeshSpec) -> TubeMesh {
        let b = &design.balloon;
        match spec.straight_mm {
            Some(coarse) if coarse > spec.element_mm => {
                let zones = fine_zones(design, coarse);
                let ring_y = graded_rings(b.length_mm, &zones, spec.element_mm, coarse);
                let around = spec
                    .around
                    .unwrap_or_else(|| MeshSpec::around_for(b.radius_mm, spec.element_mm));
                Self::with_rings(
                    b.radius_mm,
                    b.length_mm,
                    around.max(8),
                    ring_y,
                    spec.element_mm,
                )
            }
            _ => TubeMesh::new(b.radius_mm, b.length_mm, spec),
        }
    }

    /// Uniform mesh with about `spec.element_mm` edges (at least 8 around).
    pub fn new(radius: f64, length: f64, spec: MeshSpec) -> TubeMesh {
        let h = spec.element_mm;
        let around = spec
            .around
            .unwrap_or_else(|| MeshSpec::around_for(radius, h))
            .max(8);
        let segments = ((length / h).round() as usize).max(2);
        let ring_y: Vec<f64> = (0..=segments)
            .map(|k| length * k as f64 / segments as f64)
            .collect();
        Self::with_rings(radius, length, around, ring_y, h)
    }

    /// Mesh with the given ring positions (strictly increasing, from 0 to L₀).
    pub fn with_rings(
        radius: f64,
        length: f64,
        around: usize,
        ring_y: Vec<f64>,
        cap_element_mm: f64,
    ) -> TubeMesh {
        let mut nodes = Vec::new();
        for &y in &ring_y {
            for j in 0..around {
                let t = TAU * j as f64 / around as f64;
                nodes.push(Point::new(radius * t.cos(), radius * t.sin(), y));
            }
        }
        let mut triangles = Vec::new();
        let rings = ring_y.len();
        for k in 0..rings - 1 {
            band(&mut triangles, k * around, (k + 1) * around, around, k);
        }
        let tube_triangles = triangles.len();
        // Cap: rings at polar angles φ from the rim towards the pole, then a fan.
        let cap_rings = (((FRAC_PI_2 * radius) / cap_element_mm).round() as usize).max(2);
        let mut previous = (rings - 1) * around;
        for m in 1..cap_rings {
            let phi = FRAC_PI_2 * m as f64 / cap_rings as f64;
            let start = nodes.len();
            for j in 0..around {
                let t = TAU * j as f64 / around as f64;
                let r = radius * phi.cos();
                nodes.push(Point::new(
                    r * t.cos(),
                    r * t.sin(),
                    length + radius * phi.sin(),
                ));
            }
            band(&mut triangles, previous, start, around, rings - 1 + m);
            previous = start;
        }
        let pole = nodes.len();
        nodes.push(Point::new(0.0, 0.0, length + radius));
        for j in 0..around {
            triangles.push([previous + j, previous + (j + 1) % around, pole]);
        }
        let mut fixed = vec![false; nodes.len()];
        fixed[..around].fill(true);
        TubeMesh {
            nodes,
            triangles,
            tube_triangles,
            around,
            ring_y,
            fixed,
            radius,
            length,
        }
    }

    /// The same mesh on a balloon of reference length `length`: the tube's
    /// rings at the same fractions of it, the cap moved with its rim. Node
    /// k stays the same material point of the stretched balloon (as the
    /// refine's length variable stretches the patches with it).
    ///
    /// At the mesh's own length every node stays exactly where it is (the
    /// cap's shift is 0, not a rounding of (z + L) − L), so a model on the
    /// stretched mesh shares every element a change leaves alone with the
    /// model on this one ([`Model::gradient_change`](super::model::Model::gradient_change)).
    pub fn stretched_to(&self, length: f64) -> TubeMesh {
        let scale = length / self.length;
        let shift = length - self.length;
        let tube_nodes = self.ring_y.len() * self.around;
        let nodes = self
            .nodes
            .iter()
            .enumerate()
            .map(|(k, p)| {
                let z = if k < tube_nodes {
                    p.z * scale
                } else {
                    p.z + shift
                };
                Point::new(p.x, p.y, z)
            })
            .collect();
        TubeMesh {
            nodes,
            ring_y: self.ring_y.iter().map(|y| y * scale).collect(),
            length,
            ..self.clone()
        }
    }

    /// Unrolled coordinates (X, Y) of a tube node.
    pub fn unrolled(&self, node: usize) -> [f64; 2] {
        let j = node % self.around;
        let k = node / self.around;
        [
            TAU * self.radius * j as f64 / self.around as f64,
            self.ring_y[k],
        ]
    }

    pub fn circumference(&self) -> f64 {
        TAU * self.radius
    }
}

/// Two triangles per quad between ring `lower` and ring `upper`, diagonals
/// alternating in a checkerboard; outward normals.
fn band(triangles: &mut Vec<[usize; 3]>, lower: usize, upper: usize, around: usize, row: usize) {
    for j in 0..around {
        let jn = (j + 1) % around;
        let (a, b, c, d) = (lower + j, lower + jn, upper + jn, upper + j);
        if (row + j).is_multiple_of(2) {
            triangles.push([a, b, c]);
            triangles.push([a, c, d]);
        } else {
            triangles.push([a, b, d]);
            triangles.push([b, c, d]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_users_options_choose_the_mesh() {
        let default = MeshSpec::default_simulation();
        assert_eq!(MeshSpec::from_options(None, None), default);
        assert_eq!(
            MeshSpec::from_options(Some(2.0), None),
            MeshSpec::uniform(2.0)
        );
        assert_eq!(
            MeshSpec::from_options(Some(1.0), Some(8.0)),
            MeshSpec::graded(1.0, 8.0)
        );
        assert_eq!(
            MeshSpec::from_options(None, Some(6.0)),
            MeshSpec::graded(default.element_mm, 6.0)
        );
    }

    #[test]
    fn a_mesh_spec_names_itself() {
        assert_eq!(MeshSpec::uniform(0.5).to_string(), "uniform 0.5 mm");
        assert_eq!(
            MeshSpec::graded(0.5, 4.0).to_string(),
            "graded 0.5 mm (bare stretches 4 mm)"
        );
        let search = MeshSpec {
            around: Some(16),
            ..MeshSpec::graded(3.0, 6.0)
        };
        assert_eq!(
            search.to_string(),
            "graded 3 mm (bare stretches 6 mm), 16 around"
        );
    }

    /// Stretched to its own length a mesh is the same node for node, caps
    /// included (a linearised change shares the elements it leaves alone
    /// only then), at any length; and stretched to another length its
    /// rings keep their fractions of it.
    #[test]
    fn a_mesh_stretched_to_its_own_length_is_itself() {
        for k in 0..40 {
            let length = 80.0 + 23.456_789_123 * k as f64;
            let design = crate::design::Design {
                balloon: crate::design::Balloon {
                    length_mm: length,
                    ..crate::design::Balloon::default()
                },
                ..crate::design::Design::reference(vec![])
            };
            let mesh = TubeMesh::for_design(&design, MeshSpec::graded(1.0, 4.0));
            let same = mesh.stretched_to(mesh.length).nodes == mesh.nodes;
            assert!(same, "{length} mm: nodes moved");
            let longer = mesh.stretched_to(1.5 * mesh.length);
            for (a, b) in longer.ring_y.iter().zip(&mesh.ring_y) {
                assert!((a / longer.length - b / mesh.length).abs() < 1e-12);
            }
        }
    }

    /// The estimate counts the rings a uniform mesh of the fine size would
    /// have (the reference tube at 0.5 mm: 40 around, 585 rings), within 5 %
    /// of the nodes built; a graded mesh has fewer.
    #[test]
    fn the_node_estimate_counts_every_ring_at_the_fine_size() {
        let nodes = MeshSpec::graded(0.5, 4.0).most_nodes(3.18, 292.0);
        assert_eq!(nodes, 40.0 * 586.0);
        let uniform = TubeMesh::new(3.18, 292.0, MeshSpec::uniform(0.5))
            .nodes
            .len() as f64;
        assert!(
            (uniform / nodes - 1.0).abs() < 0.05,
            "{uniform} against {nodes}"
        );
        let design = crate::design::Design::reference(vec![]);
        let graded = TubeMesh::for_design(&design, MeshSpec::graded(0.5, 4.0));
        assert!(
            (graded.nodes.len() as f64) < nodes,
            "{}",
            graded.nodes.len()
        );
    }
}
