//! How far the kinematic start is from the solution, by the Newton
//! iterations a cold solve takes from it, for a range of curvature scales
//! (`fe::kinematic`; `simulate` takes `calibrated_scale`): on ten curves'
//! KSA seeds and CMA-ES-sized perturbations of them (σ 0.2 in the unit
//! cube), on the search and the verification meshes of the `draft` preset,
//! the reference scene or (`incompressible`) its materials incompressible.
//!
//! `cargo run --release -p patchwork-core --example kinematic_scale -- [candidates] [scale ...] [incompressible]`
//! (defaults 4 candidates per curve besides the seed, scales 1.5 2 2.5 3).

use std::time::Instant;

#[path = "common/seeds.rs"]
mod seeds;

use patchwork_core::cmaes::SeededRng;
use patchwork_core::design::Design;
use patchwork_core::fe::kinematic::kinematic_state;
use patchwork_core::fe::mesh::{MeshSpec, TubeMesh};
use patchwork_core::fe::model::Model;
use patchwork_core::fe::newton::{NewtonOptions, PatternCache, Solver};
use patchwork_core::fe::section::CutElements;
use patchwork_core::fe::tube_theory::inflate_tube;
use patchwork_core::inverse::Fidelity;
use seeds::{curves, designs, median};

/// Newton iterations and milliseconds of a cold solve from the kinematic
/// start at `scale`; none if it fails.
fn solve(
    design: &Design,
    mesh: MeshSpec,
    scale: f64,
    patterns: &PatternCache,
) -> Option<(usize, f64)> {
    let b = &design.balloon;
    let tube = inflate_tube(&b.material, design.pressure_mpa(), b.radius_mm, b.wall_mm)?;
    let model = Model::new(
        design,
        TubeMesh::for_design(design, mesh),
        CutElements::default(),
    );
    let solver = Solver::new(&model, patterns).ok()?;
    let started = Instant::now();
    let mut x = kinematic_state(design, &model.mesh, tube, scale);
    let stats = (solver.solve(&model, &model.sections, &mut x, &NewtonOptions::default())).ok()?;
    Some((stats.iterations, started.elapsed().as_secs_f64() * 1e3))
}

fn main() {
    let (words, numbers): (Vec<String>, Vec<String>) =
        (std::env::args().skip(1)).partition(|a| a.parse::<f64>().is_err());
    let incompressible = words.iter().any(|w| w == "incompressible");
    let args: Vec<f64> = (numbers.iter())
        .map(|a| a.parse().expect("numbers: candidates scale ..."))
        .collect();
    let count = args.first().map_or(4, |c| *c as usize);
    let scales = match args.len() > 1 {
        true => args[1..].to_vec(),
        false => vec![1.5, 2.0, 2.5, 3.0],
    };
    let tuning = Fidelity::Draft.tuning(Design::reference(vec![]).balloon.radius_mm);
    let meshes = [
        ("search", tuning.search_mesh),
        ("verify", tuning.verify_mesh),
    ];
    let patterns = PatternCache::default();
    let mut rng = SeededRng::new(1);
    let sets: Vec<(String, Vec<Design>)> = (curves().into_iter())
        .map(|(name, curve)| (name, designs(&curve, count, &mut rng, incompressible)))
        .collect();
    let header: Vec<String> = scales.iter().map(|s| format!("scale {s}")).collect();
    println!("mesh | curve | {}", header.join(" | "));
    for (mesh_name, mesh) in meshes {
        let mut all: Vec<Vec<f64>> = vec![Vec::new(); scales.len()];
        for (name, designs) in &sets {
            let cells: Vec<String> = (scales.iter().enumerate())
                .map(|(k, &scale)| {
                    let solved: Vec<(usize, f64)> = (designs.iter())
                        .filter_map(|d| solve(d, mesh, scale, &patterns))
                        .collect();
                    all[k].extend(solved.iter().map(|s| s.0 as f64));
                    let iterations = median(solved.iter().map(|s| s.0 as f64).collect());
                    let ms = median(solved.iter().map(|s| s.1).collect());
                    let failed = designs.len() - solved.len();
                    format!("{iterations:.0} its, {ms:.0} ms, {failed} failed")
                })
                .collect();
            println!("{mesh_name} | {name} | {}", cells.join(" | "));
        }
        let medians: Vec<String> = all
            .into_iter()
            .map(|v| format!("{:.0}", median(v)))
            .collect();
        println!("{mesh_name} | all: median its | {}", medians.join(" | "));
    }
}
