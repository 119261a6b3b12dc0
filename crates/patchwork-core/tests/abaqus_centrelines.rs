//! The authors' ABAQUS/Explicit output (data/abaqus/README.md) against
//! Patchwork's model of the same balloon: Arruda–Boyce wall and neo-Hookean
//! patches with K₀/μ₀ = 20 (ABAQUS/Explicit's assumption for D = 0).
//!
//! The rings are evenly spaced on the uninflated balloon, so the distance
//! between neighbouring ring centres is the local axial stretch times
//! 292/(rings − 1) mm. ABAQUS's `Run.py` wraps the sheet's X round the tube
//! the other way from Patchwork (x = R cos(X/R), z = R sin(X/R) about the y
//! axis), so the same patches make the mirror image: the ABAQUS points are
//! mirrored (z → −z) before the rigid alignment.
//!
//! Measured (cargo test --release --test abaqus_centrelines -- --nocapture):
//! six patches, ABAQUS 973.8 mm long, bare ring spacing 14.48 mm; Patchwork
//! on its verification mesh 968.1 mm (−0.6 %), 14.52 mm, shape error 3.1 %
//! of length; on ABAQUS's element size (2 mm, 10 round) 974.9 mm, 14.55 mm,
//! 4.5 % (a 2 mm model's patches bend differently from the converged
//! model's: its centreline lies 0.6–1.7 % of the length from a 0.25 mm
//! solution's on four designs, docs/studies.md "Loading the facets"; with
//! the facets loaded by the bare pressure it was 885.5 mm long, 1.8 %).
//! What is left between them: ABAQUS's bare stretches are not straight
//! (about 1.5° per ring, a curvature no uniform tube in equilibrium has: its
//! explicit run ends with the balloon still moving, or its free quad mesh
//! bends it), which accounts for most of its 409° of total turning against
//! Patchwork's 333°; the turn at each patch agrees within a few degrees.

use patchwork_core::curve::{Curve, Point, Units, read_curve, shape_error};
use patchwork_core::design::{Design, Patch};
use patchwork_core::fe::mesh::MeshSpec;
use patchwork_core::fe::{SimulateOptions, simulate};
use patchwork_core::material::Compressibility;

const SIX_PATCHES: &str = include_str!("../data/abaqus/six_patches_centreline.csv");
const HELICAL: &str = include_str!("../data/abaqus/helical_patch_centreline.csv");

/// The ABAQUS ring centres, mirrored into Patchwork's handedness.
fn abaqus(text: &str) -> Curve {
    let rings = read_curve(text, Units::Mm).unwrap();
    Curve::from_points(
        rings
            .points()
            .iter()
            .map(|p| Point::new(p.x, p.y, -p.z))
            .collect(),
    )
    .unwrap()
}

fn spacings(curve: &Curve) -> Vec<f64> {
    curve
        .points()
        .windows(2)
        .map(|w| (w[1] - w[0]).norm())
        .collect()
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// The paper's scene, which is the reference scene: the authors' balloon
/// and patch, both with K₀/μ₀ = 20 as ABAQUS/Explicit takes their D = 0.
fn paper(patches: Vec<Patch>) -> Design {
    let design = Design::reference(patches);
    for material in [&design.balloon.material, &design.patch.material] {
        assert_eq!(material.compressibility, Compressibility::abaqus_explicit());
    }
    design
}

fn six_patches() -> Design {
    let patch = |x_mm, y_mm, h_mm| Patch {
        x_mm,
        y_mm,
        h_mm,
        w_mm: 1.5,
        theta_deg: 0.0,
    };
    paper(vec![
        patch(4.0, 43.93, 17.0),
        patch(4.0, 87.88, 17.0),
        patch(8.99, 128.21, 17.0),
        patch(8.99, 163.87, 17.0),
        patch(4.0, 204.84, 18.46),
        patch(4.0, 248.78, 18.44),
    ])
}

/// Simulates on `mesh` with ABAQUS's rings; (length, median spacing, shape
/// error % of the ABAQUS length) against `reference`.
fn against(design: &Design, mesh: MeshSpec, reference: &Curve) -> (f64, f64, f64) {
    let options = SimulateOptions {
        mesh,
        rings: reference.len(),
        ..SimulateOptions::default()
    };
    let sim = simulate(design, &options).unwrap();
    let error = shape_error(&sim.centreline, reference, 400).unwrap();
    (
        sim.centreline.length(),
        median(spacings(&sim.centreline)),
        error.percent_of_length,
    )
}

#[test]
fn six_patches_reproduce_the_abaqus_centreline() {
    let reference = abaqus(SIX_PATCHES);
    let (length, spacing) = (reference.length(), median(spacings(&reference)));
    println!("ABAQUS: {length:.1} mm, bare ring spacing {spacing:.2} mm");
    let verification = against(&six_patches(), MeshSpec::default_simulation(), &reference);
    let theirs = against(&six_patches(), MeshSpec::uniform(2.0), &reference);
    for (name, (l, s, e)) in [
        ("verification mesh", verification),
        ("2 mm (ABAQUS's)", theirs),
    ] {
        println!(
            "Patchwork, {name}: {l:.1} mm ({:+.1} %), spacing {s:.2} mm ({:+.1} %), shape error {e:.2} %",
            100.0 * (l / length - 1.0),
            100.0 * (s / spacing - 1.0)
        );
    }
    let (l, s, e) = verification;
    assert!((l / length - 1.0).abs() < 0.05, "length {l} vs {length}");
    assert!((s / spacing - 1.0).abs() < 0.05, "spacing {s} vs {spacing}");
    // The goal is 2 %; the converged model is 2.9 % from ABAQUS's
    // coarse explicit run (see the module's note).
    assert!(e < 3.5, "shape error {e} %");
    let (l, _, e) = theirs;
    assert!(
        (l / length - 1.0).abs() < 0.02,
        "2 mm: length {l} vs {length}"
    );
    assert!(e < 5.0, "2 mm: shape error {e} %");
}

/// The first commit's output is of a helical patch about 169 mm long (see
/// data/abaqus/README.md), not the one its `Run.py` names: its bare
/// stretches are compared with the compressible tube's closed form.
#[test]
fn helical_output_ring_spacings_match_bare_and_patched_stretches() {
    let reference = abaqus(HELICAL);
    let s = spacings(&reference);
    let (bare, patched) = (median(s[3..12].to_vec()), median(s[16..48].to_vec()));
    let ring = 292.0 / (reference.len() - 1) as f64;
    let bare_design = paper(vec![]);
    let tube = patchwork_core::fe::tube_theory::inflate_tube(
        &bare_design.balloon.material,
        bare_design.pressure_mpa(),
        bare_design.balloon.radius_mm,
        bare_design.balloon.wall_mm,
    )
    .unwrap();
    println!(
        "ABAQUS helical: bare stretch {:.3}, under the patch {:.3}; theory bare {:.3}",
        bare / ring,
        patched / ring,
        tube.axial
    );
    assert!((bare / ring / tube.axial - 1.0).abs() < 0.05);
    // Under the patch ABAQUS's stretch is 2.79; Patchwork's simulation of
    // the patch `Run.py` names (137 mm) gives 2.74 on its verification mesh,
    // but that solve takes minutes, and the patch is not the one simulated.
    assert!(
        patched / ring < 0.8 * bare / ring,
        "the patch holds the wall back"
    );
}
