//! What a design search's candidates cost to simulate, against the seed: the
//! Hilbert reference scene's KSA patches perturbed as CMA-ES's first
//! generation perturbs them (unit cube around the seed, step σ), each solved
//! cold on one mesh. Prints per candidate the time, Newton iterations, the
//! start that worked (kinematic, or continuation steps from the straight
//! tube) and the outcome.
//!
//! `cargo run --release -p patchwork-core --example candidate_solves -- [element_mm] [straight_mm] [count] [sigma]`
//! (defaults 1, 4, 12, 0.2: the model the `draft` preset polishes on and the
//! `fine` preset searches on).

use std::time::Instant;

use patchwork_core::cmaes::SeededRng;
use patchwork_core::curve::ReferenceCurve;
use patchwork_core::design::Design;
use patchwork_core::fe::mesh::MeshSpec;
use patchwork_core::fe::{SimulateOptions, simulate};
use patchwork_core::inverse::{DesignSpace, Freedom, VariableBounds};
use patchwork_core::ksa::{KsaParams, ksa};

fn main() {
    let args: Vec<f64> = std::env::args()
        .skip(1)
        .map(|a| {
            a.parse()
                .expect("numbers: element_mm straight_mm count sigma")
        })
        .collect();
    let element = args.first().copied().unwrap_or(1.0);
    let straight = args.get(1).copied().unwrap_or(4.0);
    let count = args.get(2).copied().unwrap_or(12.0) as usize;
    let sigma = args.get(3).copied().unwrap_or(0.2);
    let seed = ksa(&ReferenceCurve::Hilbert.curve(), &KsaParams::default()).expect("valid");
    let design = Design::reference(seed.patches);
    let mesh = if straight > element {
        MeshSpec::graded(element, straight)
    } else {
        MeshSpec::uniform(element)
    };
    let options = SimulateOptions {
        mesh,
        ..SimulateOptions::default()
    };
    let space = DesignSpace::new(
        design.patches.clone(),
        Freedom::default(),
        &VariableBounds::default(),
        design.balloon.length_mm,
    )
    .expect("valid bounds");
    let centre = space.seed_point();
    let mut rng = SeededRng::new(1);
    println!("candidate | ms | Newton its | factorisations | continuation steps | outcome");
    let mut times = Vec::new();
    for k in 0..=count {
        let u: Vec<f64> = if k == 0 {
            centre.clone()
        } else {
            centre
                .iter()
                .map(|c| (c + sigma * rng.normal()).clamp(0.0, 1.0))
                .collect()
        };
        let candidate = Design {
            patches: space.patches(&u),
            ..design.clone()
        };
        let t = Instant::now();
        let result = simulate(&candidate, &options);
        let ms = t.elapsed().as_secs_f64() * 1e3;
        times.push(ms);
        let name = if k == 0 { "seed".into() } else { k.to_string() };
        match result {
            Ok(sim) => println!(
                "{name} | {ms:.0} | {} | {} | {} | converged, length {:.4} mm",
                sim.stats.iterations,
                sim.stats.factorisations,
                sim.continuation_steps,
                sim.inflated_length_mm
            ),
            Err(e) => println!("{name} | {ms:.0} | | | | {e}"),
        }
    }
    times[1..].sort_by(f64::total_cmp);
    println!(
        "seed {:.0} ms; candidates median {:.0} ms, max {:.0} ms",
        times[0],
        times[1 + (times.len() - 1) / 2],
        times[times.len() - 1]
    );
}
