//! Cut elements, laminate against area average: the 30° strip of the CalculiX
//! cross-check (20 mm tube, 6 kPa) at several element sizes, printing the tip
//! ring's bend and twist, Newton iterations and time for each rule.
//!
//! cargo run --release -p patchwork-core --example cut_elements [-- 2,1,0.5,0.25]

use std::f64::consts::TAU;

use patchwork_core::curve::bend_and_twist;
use patchwork_core::design::{Balloon, Bonding, Design, Patch, PatchSpec};
use patchwork_core::fe::mesh::MeshSpec;
use patchwork_core::fe::section::CutElements;
use patchwork_core::fe::{SimulateOptions, simulate};
use patchwork_core::material::{Law, Material};

fn strip_design() -> Design {
    let (radius, length, theta) = (3.18_f64, 20.0_f64, 30.0_f64);
    let h = TAU * radius / 16.0;
    Design {
        balloon: Balloon {
            length_mm: length,
            radius_mm: radius,
            wall_mm: 0.183,
            material: Material::incompressible(Law::NeoHookean { mu_mpa: 0.317 }),
        },
        patch: PatchSpec {
            thickness_mm: 0.49,
            material: Material::incompressible(Law::NeoHookean { mu_mpa: 1.3 }),
            bonding: Bonding::Replace,
        },
        pressure_kpa: 6.0,
        patches: vec![Patch {
            x_mm: 1.5 * h + theta.to_radians().tan() * 0.5 * length,
            y_mm: 0.5 * length,
            h_mm: length / theta.to_radians().cos() + 8.0,
            w_mm: 3.0 * h * theta.to_radians().cos(),
            theta_deg: theta,
        }],
    }
}

fn main() {
    let sizes: Vec<f64> = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "2,1,0.5,0.25".into())
        .split(',')
        .map(|s| s.parse().expect("element sizes in mm, comma-separated"))
        .collect();
    let design = strip_design();
    println!("rule          h_mm   bend_deg  twist_deg  newton  steps  time_s");
    for rule in [CutElements::AreaAverage, CutElements::Laminate] {
        for &h in &sizes {
            let options = SimulateOptions {
                mesh: MeshSpec::uniform(h),
                cut_elements: rule,
                ..SimulateOptions::default()
            };
            match simulate(&design, &options) {
                Ok(sim) => {
                    let tip = sim.mesh.ring_y.len() - 1;
                    let ring = tip * sim.mesh.around..(tip + 1) * sim.mesh.around;
                    let (bend, twist) =
                        bend_and_twist(&sim.mesh.nodes[ring.clone()], &sim.positions[ring]);
                    println!(
                        "{:<12} {h:6.3} {bend:10.4} {twist:10.4} {:7} {:6} {:7.2}",
                        format!("{rule:?}"),
                        sim.stats.iterations,
                        sim.continuation_steps,
                        sim.elapsed.as_secs_f64()
                    );
                }
                Err(e) => println!("{:<12} {h:6.3} failed: {e}", format!("{rule:?}")),
            }
        }
    }
}
