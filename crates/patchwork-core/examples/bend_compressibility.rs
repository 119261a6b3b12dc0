//! How the axial patch of the CalculiX cross-check bends the tube (40 mm,
//! 6 kPa, neo-Hookean wall and patch) as the materials' K/μ varies: at small
//! strain a closed tube's axial strain scales with 1 − 2ν, so the bend is a
//! sensitive measure of compressibility (docs/studies.md, "CalculiX
//! cross-check").
//!
//! cargo run --release -p patchwork-core --example bend_compressibility [-- 0.25]

use std::f64::consts::TAU;

use patchwork_core::curve::bend_and_twist;
use patchwork_core::design::{Balloon, Bonding, Design, Patch, PatchSpec};
use patchwork_core::fe::mesh::MeshSpec;
use patchwork_core::fe::{SimulateOptions, simulate};
use patchwork_core::material::{Compressibility, Law, Material};

fn design(bulk_ratio: Option<f64>) -> Design {
    let material = |mu_mpa| {
        let law = Law::NeoHookean { mu_mpa };
        match bulk_ratio {
            Some(r) => Material::compressible(law, Compressibility::BulkRatio(r)),
            None => Material::incompressible(law),
        }
    };
    // Two element columns of a 16-around mesh, as in the cross-check.
    let h = TAU * 3.18 / 16.0;
    Design {
        balloon: Balloon {
            length_mm: 40.0,
            radius_mm: 3.18,
            wall_mm: 0.183,
            material: material(0.317),
        },
        patch: PatchSpec {
            thickness_mm: 0.49,
            material: material(1.3),
            bonding: Bonding::Replace,
        },
        pressure_kpa: 6.0,
        patches: vec![Patch {
            x_mm: 2.0 * h,
            y_mm: 20.0,
            h_mm: 15.0,
            w_mm: 2.0 * h,
            theta_deg: 0.0,
        }],
    }
}

fn main() {
    let element: f64 = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(0.25);
    let options = SimulateOptions {
        mesh: MeshSpec::uniform(element),
        ..SimulateOptions::default()
    };
    println!("| K/μ | small-strain ν | bend | hoop stretch |");
    println!("|---|---|---|---|");
    for bulk_ratio in [
        Some(15.0),
        Some(18.0),
        Some(20.0),
        Some(22.0),
        Some(25.0),
        Some(50.0),
        None,
    ] {
        let sim = match simulate(&design(bulk_ratio), &options) {
            Ok(sim) => sim,
            Err(e) => {
                println!("| {bulk_ratio:?} | solve failed: {e} | | |");
                continue;
            }
        };
        let tip = sim.mesh.ring_y.len() - 1;
        let ring = tip * sim.mesh.around..(tip + 1) * sim.mesh.around;
        let (bend, _) = bend_and_twist(&sim.mesh.nodes[ring.clone()], &sim.positions[ring]);
        // ν = (3K − 2μ) / (2 (3K + μ)).
        let (label, nu) = match bulk_ratio {
            Some(r) => (format!("{r}"), (3.0 * r - 2.0) / (2.0 * (3.0 * r + 1.0))),
            None => ("incompressible".to_string(), 0.5),
        };
        println!(
            "| {label} | {nu:.4} | {bend:.4}° | {:.3} |",
            sim.hoop_stretch_mid
        );
    }
}
