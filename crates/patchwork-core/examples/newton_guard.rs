//! What Newton's definiteness guard saves: the Hilbert reference scene (six
//! KSA patches) solved with the guard off and on, interleaved run by run, cold
//! (kinematic start) and from a coarser model's state carried onto the mesh
//! (as the corrected refine and the final refine start their solves).
//!
//! `cargo run --release -p patchwork-core --example newton_guard -- [runs]`
//!
//! Prints, per case and setting, the median wall time of the solve and its
//! Newton iterations and factorisations, and the largest distance between
//! the two settings' centrelines (the same equilibrium, or not).

use std::time::Instant;

use patchwork_core::curve::ReferenceCurve;
use patchwork_core::design::Design;
use patchwork_core::fe::mesh::MeshSpec;
use patchwork_core::fe::newton::NewtonOptions;
use patchwork_core::fe::{SimulateOptions, Simulation, simulate, simulate_from};
use patchwork_core::ksa::{KsaParams, ksa};

fn options(mesh: MeshSpec, guard: bool) -> SimulateOptions {
    SimulateOptions {
        mesh,
        newton: NewtonOptions {
            definiteness_guard: guard,
            ..NewtonOptions::default()
        },
        ..SimulateOptions::default()
    }
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    let runs: usize = std::env::args()
        .nth(1)
        .map_or(3, |a| a.parse().expect("runs is a number"));
    let seed = ksa(&ReferenceCurve::Hilbert.curve(), &KsaParams::default()).expect("valid");
    let design = Design::reference(seed.patches);
    let search = MeshSpec {
        element_mm: 3.0,
        around: Some(MeshSpec::around_for(design.balloon.radius_mm, 2.0)),
        straight_mm: Some(6.0),
    };
    let graded_1 = MeshSpec::graded(1.0, 4.0);
    let graded_half = MeshSpec::graded(0.5, 4.0);
    let uniform_half = MeshSpec::uniform(0.5);
    let state = |mesh| simulate(&design, &options(mesh, true)).expect("the start solves");
    let from_search = state(search);
    let from_graded_1 = state(graded_1);
    let from_graded_half = state(graded_half);
    let cases: [(&str, MeshSpec, Option<&Simulation>); 7] = [
        ("cold, uniform 2 mm", MeshSpec::uniform(2.0), None),
        ("cold, graded 1 mm", graded_1, None),
        ("cold, graded 0.5 mm", graded_half, None),
        (
            "graded 0.5 mm from the search mesh (3 mm)",
            graded_half,
            Some(&from_search),
        ),
        (
            "graded 0.5 mm from graded 1 mm",
            graded_half,
            Some(&from_graded_1),
        ),
        ("cold, uniform 0.5 mm", uniform_half, None),
        (
            "uniform 0.5 mm from graded 0.5 mm",
            uniform_half,
            Some(&from_graded_half),
        ),
    ];
    println!("| case | guard | solve s (median of {runs}) | Newton its | factorisations |");
    println!("|---|---|---|---|---|");
    for (name, mesh, start) in cases {
        let mut rows: [(Vec<f64>, usize, usize, Option<Simulation>); 2] = Default::default();
        for _ in 0..runs {
            for (guard, row) in [false, true].into_iter().zip(rows.iter_mut()) {
                let t = Instant::now();
                let sim = simulate_from(&design, &options(mesh, guard), start).expect("converges");
                row.0.push(t.elapsed().as_secs_f64());
                (row.1, row.2) = (sim.stats.iterations, sim.stats.factorisations);
                row.3 = Some(sim);
            }
        }
        for (guard, row) in ["off", "on"].into_iter().zip(&rows) {
            println!(
                "| {name} | {guard} | {:.3} | {} | {} |",
                median(row.0.clone()),
                row.1,
                row.2
            );
        }
        if let [(.., Some(off)), (.., Some(on))] = &rows {
            let gap = off.centreline.largest_gap(&on.centreline);
            println!("|  | largest centreline gap off/on: {gap:.2e} mm | | | |");
        }
    }
}
