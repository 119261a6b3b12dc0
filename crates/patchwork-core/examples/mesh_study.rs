//! Mesh convergence of the forward model on the reference scene (the six KSA
//! patches of the Hilbert curve, 20 kPa) and on a sparse scene (one patch on a
//! 300 mm balloon): uniform meshes, graded meshes (local refinement) and finer
//! cross-sections, each against a uniform 0.5 mm solution.
//!
//! `cargo run --release -p patchwork-core --example mesh_study [runs] [average]`
//! (about five minutes with the default three runs; times are medians).
//! `average` models cut elements by area average instead of the laminate.

use patchwork_core::curve::ReferenceCurve;
use patchwork_core::design::{Balloon, Design, Patch};
use patchwork_core::fe::mesh::MeshSpec;
use patchwork_core::fe::section::CutElements;
use patchwork_core::fe::{SimulateOptions, Simulation, simulate};
use patchwork_core::ksa::{KsaParams, ksa};

fn spec(element_mm: f64, around: Option<usize>, straight_mm: Option<f64>) -> MeshSpec {
    MeshSpec {
        element_mm,
        around,
        straight_mm,
    }
}

fn label(m: &MeshSpec) -> String {
    let mut text = format!("{} mm", m.element_mm);
    if let Some(n) = m.around {
        text.push_str(&format!(", {n} around"));
    }
    if let Some(s) = m.straight_mm {
        text.push_str(&format!(", bare stretches {s} mm"));
    }
    text
}

fn study(name: &str, design: &Design, meshes: &[MeshSpec], runs: usize, cut_elements: CutElements) {
    println!("\n{name}\n");
    println!(
        "| mesh | rings | unknowns | Newton its | solve s (median of {runs}) | inflated length mm | largest centreline gap to 0.5 mm (mm) |"
    );
    println!("|---|---|---|---|---|---|---|");
    let reference = simulate(
        design,
        &SimulateOptions {
            mesh: MeshSpec::uniform(0.5),
            cut_elements,
            ..SimulateOptions::default()
        },
    )
    .expect("the reference solve converges");
    for mesh in meshes {
        let options = SimulateOptions {
            mesh: *mesh,
            cut_elements,
            ..SimulateOptions::default()
        };
        let mut times = Vec::new();
        let mut last: Option<Simulation> = None;
        for _ in 0..runs {
            let sim = simulate(design, &options).expect("converges");
            times.push(sim.elapsed.as_secs_f64());
            last = Some(sim);
        }
        times.sort_by(f64::total_cmp);
        let sim = last.expect("at least one run");
        println!(
            "| {} | {} | {} | {} | {:.3} | {:.2} | {:.2} |",
            label(mesh),
            sim.mesh.ring_y.len(),
            3 * sim.mesh.nodes.len(),
            sim.stats.iterations,
            times[times.len() / 2],
            sim.inflated_length_mm,
            sim.centreline.largest_gap(&reference.centreline)
        );
    }
    println!(
        "| 0.5 mm (reference) | {} | {} | {} | {:.3} (one run) | {:.2} | 0 |",
        reference.mesh.ring_y.len(),
        3 * reference.mesh.nodes.len(),
        reference.stats.iterations,
        reference.elapsed.as_secs_f64(),
        reference.inflated_length_mm
    );
}

fn main() {
    let runs: usize = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(3);
    let cut_elements: CutElements = std::env::args()
        .nth(2)
        .map_or(Ok(CutElements::Laminate), |w| w.parse())
        .unwrap_or_else(|e| panic!("{e}"));
    println!("cut elements: {cut_elements:?}");
    let seed = ksa(&ReferenceCurve::Hilbert.curve(), &KsaParams::default()).expect("valid");
    let hilbert = Design::reference(seed.patches);
    study(
        "Reference scene: six KSA patches of the Hilbert curve, 292 mm balloon",
        &hilbert,
        &[
            MeshSpec::uniform(3.0),
            MeshSpec::uniform(2.0),
            MeshSpec::graded(2.0, 6.0),
            spec(2.0, Some(20), None),
            MeshSpec::uniform(1.0),
            MeshSpec::graded(1.0, 4.0),
        ],
        runs,
        cut_elements,
    );
    let sparse = Design {
        balloon: Balloon {
            length_mm: 300.0,
            ..Balloon::default()
        },
        ..Design::reference(vec![Patch {
            x_mm: 0.0,
            y_mm: 150.0,
            h_mm: 20.0,
            w_mm: 2.5,
            theta_deg: 15.0,
        }])
    };
    study(
        "Sparse scene: one patch (20 × 2.5 mm, Θ = 15°) on a 300 mm balloon",
        &sparse,
        &[
            MeshSpec::uniform(2.0),
            MeshSpec::graded(2.0, 6.0),
            spec(2.0, Some(20), Some(6.0)),
            MeshSpec::uniform(1.0),
            MeshSpec::graded(1.0, 4.0),
            MeshSpec::graded(1.0, 8.0),
            MeshSpec::graded(0.5, 4.0),
        ],
        runs,
        cut_elements,
    );
}
