//! Cold solves with and without the coarse start: the KSA seeds of the
//! authors' three curves on the verification mesh (0.5 mm, 4 mm along bare
//! stretches), on the paper's compressible balloon and on incompressible
//! materials. Prints Newton iterations (the coarse model's included), wall
//! time and how far apart the two end states' centrelines are.
//!
//! `cargo run --release -p patchwork-core --example coarse_start`

use std::time::Instant;

use patchwork_core::curve::ReferenceCurve;
use patchwork_core::design::Design;
use patchwork_core::fe::mesh::MeshSpec;
use patchwork_core::fe::{SimulateOptions, simulate};
use patchwork_core::ksa::{KsaParams, ksa};
use patchwork_core::material::Compressibility;

fn main() {
    println!("curve | materials | kinematic start: its, s | coarse start: its, s | gap mm");
    for curve in [
        ReferenceCurve::Hilbert,
        ReferenceCurve::Spring,
        ReferenceCurve::Pancake,
    ] {
        let seed = ksa(&curve.curve(), &KsaParams::default()).expect("valid curve");
        for (name, compressibility) in [
            ("K0/mu0 = 20", Compressibility::abaqus_explicit()),
            ("incompressible", Compressibility::Incompressible),
        ] {
            let design =
                Design::reference(seed.patches.clone()).with_compressibility(compressibility);
            let solve = |coarse_start: bool| {
                let options = SimulateOptions {
                    mesh: MeshSpec::graded(0.5, 4.0),
                    coarse_start,
                    ..SimulateOptions::default()
                };
                let t = Instant::now();
                let sim = simulate(&design, &options).expect("converges");
                (sim, t.elapsed().as_secs_f64())
            };
            let ((kinematic, tk), (coarse, tc)) = (solve(false), solve(true));
            println!(
                "{curve:?} | {name} | {}, {tk:.2} | {}, {tc:.2} | {:.1e}",
                kinematic.stats.iterations,
                coarse.stats.iterations,
                kinematic.centreline.largest_gap(&coarse.centreline)
            );
        }
    }
}
