//! How far each mesh a user meets puts a patched centreline from a uniform
//! 0.25 mm solution of the same design: the shape error between the two
//! (RMS after the best rigid alignment, % of the fine centreline's length,
//! as designs are judged), their largest gap at equal fractions of length
//! in the clamp's frame, the inflated length, Newton iterations and the
//! wall time of one cold solve (one thread). The designs are the Hilbert
//! curve's KSA seed (the reference scene) and each design.json given
//! (what `patchwork design` writes).
//!
//! `cargo run --release -p patchwork-core --example patched_convergence -- [DESIGN.json…]`
//! (a 0.25 mm solve of the Hilbert seed takes about 12 s).

use std::time::Instant;

use patchwork_core::curve::{Curve, ReferenceCurve, shape_error};
use patchwork_core::design::Design;
use patchwork_core::fe::mesh::MeshSpec;
use patchwork_core::fe::{SimulateOptions, simulate};
use patchwork_core::ksa::{KsaParams, ksa};

#[path = "common/design_json.rs"]
mod design_json;

/// Samples of the comparisons.
const SAMPLES: usize = 200;

/// The largest distance (mm) between `a` and `b` at equal fractions of
/// their lengths, both in the clamp's frame.
fn largest_gap(a: &Curve, b: &Curve) -> f64 {
    let (a, b) = (a.resample(SAMPLES), b.resample(SAMPLES));
    let (a, b) = (a.expect("a centreline"), b.expect("a centreline"));
    (a.points().iter().zip(b.points()))
        .map(|(p, q)| (p - q).norm())
        .fold(0.0, f64::max)
}

/// The fine solution first, then the meshes compared with it.
fn meshes() -> [(&'static str, MeshSpec); 6] {
    [
        ("uniform 0.25 mm", MeshSpec::uniform(0.25)),
        ("uniform 0.5 mm", MeshSpec::uniform(0.5)),
        (
            "graded 0.5 / 4 mm (default)",
            MeshSpec::default_simulation(),
        ),
        ("graded 1 / 4 mm", MeshSpec::graded(1.0, 4.0)),
        ("graded 1.25 / 6 mm (quick)", MeshSpec::graded(1.25, 6.0)),
        ("graded 2 / 6 mm", MeshSpec::graded(2.0, 6.0)),
    ]
}

fn main() {
    let seed = ksa(&ReferenceCurve::Hilbert.curve(), &KsaParams::default()).expect("a seed");
    let mut designs = vec![("Hilbert seed".to_string(), Design::reference(seed.patches))];
    for path in std::env::args().skip(1) {
        let design = design_json::design_of(&path);
        designs.push((path, design));
    }
    println!(
        "| design | mesh | shape error to 0.25 mm, % | largest gap, mm | inflated mm | Newton its | solve ms |"
    );
    println!("|---|---|---|---|---|---|---|");
    for (name, design) in &designs {
        let mut fine = None;
        for (mesh_name, mesh) in meshes() {
            let options = SimulateOptions {
                mesh,
                ..SimulateOptions::default()
            };
            let started = Instant::now();
            let solved = simulate(design, &options).expect("the design inflates");
            let ms = started.elapsed().as_secs_f64() * 1e3;
            let fine = fine.get_or_insert_with(|| solved.centreline.clone());
            let error = shape_error(&solved.centreline, fine, SAMPLES).expect("a centreline");
            println!(
                "| {name} | {mesh_name} | {:.3} | {:.1} | {:.1} | {} | {ms:.0} |",
                error.percent_of_length,
                largest_gap(&solved.centreline, fine),
                solved.inflated_length_mm,
                solved.stats.iterations
            );
        }
    }
}
