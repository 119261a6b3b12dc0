//! How close two rods come to the FE model: the rod of FE-fitted patches
//! (`rod::RodTable`, computed first on the verification mesh over the
//! default bounds) and the kinematic rod (`fe::kinematic::rod_frames`: each
//! cross-section's bend from the equal-force stretch of its wall, integrated
//! from the clamp) for a range of curvature scales:
//! on ten curves' KSA seeds and perturbations of them, and on the round
//! trips' random designs (4–12 patches on a 400 mm balloon). Shape error of
//! the rod's centreline against the FE centreline on the `draft`
//! verification mesh (root-mean-square distance at equal fractions of
//! length after the best rigid alignment, % of the FE centreline's length),
//! beside that of the FE model the `draft` search runs on (its 3 mm mesh),
//! and each model's time for one design.
//!
//! `cargo run --release -p patchwork-core --example rod_accuracy -- [candidates] [scale ...]`
//! (defaults 2 candidates per curve besides the seed, scales 2 2.5 3).

#[path = "common/seeds.rs"]
mod seeds;

use std::time::Instant;

use patchwork_core::cmaes::SeededRng;
use patchwork_core::curve::{Curve, Point, shape_error};
use patchwork_core::design::Design;
use patchwork_core::design::random::round_trip_designs;
use patchwork_core::fe::kinematic::rod_frames;
use patchwork_core::fe::tube_theory::inflate_tube;
use patchwork_core::fe::{SimulateOptions, simulate};
use patchwork_core::inverse::{Fidelity, VariableBounds};
use patchwork_core::rod::RodTable;
use seeds::{curves, designs, median};

/// Rod cross-sections per uninflated millimetre.
const PER_MM: f64 = 2.0;

/// The kinematic rod's centreline of `design` at curvature `scale`.
fn rod(design: &Design, scale: f64) -> Option<Curve> {
    let b = &design.balloon;
    let state = inflate_tube(&b.material, design.pressure_mpa(), b.radius_mm, b.wall_mm)?;
    let n = (b.length_mm * PER_MM).ceil() as usize;
    let heights: Vec<f64> = (1..=n).map(|k| b.length_mm * k as f64 / n as f64).collect();
    let frames = rod_frames(design, &heights, state, scale);
    let points: Vec<Point> = std::iter::once(Point::zeros())
        .chain(frames.iter().map(|(centre, _)| *centre))
        .collect();
    Curve::from_points(points).ok()
}

/// "median % (worst w)".
fn summary(errors: &[f64]) -> String {
    let worst = errors.iter().copied().fold(0.0, f64::max);
    format!("{:.1} % (worst {worst:.1})", median(errors.to_vec()))
}

fn main() {
    let args: Vec<f64> = (std::env::args().skip(1))
        .map(|a| a.parse().expect("numbers: candidates scale ..."))
        .collect();
    let count = args.first().map_or(2, |c| *c as usize);
    let scales = match args.len() > 1 {
        true => args[1..].to_vec(),
        false => vec![2.0, 2.5, 3.0],
    };
    let radius = Design::reference(vec![]).balloon.radius_mm;
    let tuning = Fidelity::Draft.tuning(radius);
    let options = SimulateOptions {
        mesh: tuning.verify_mesh,
        threads: 1,
        ..SimulateOptions::default()
    };
    let search = SimulateOptions {
        mesh: tuning.search_mesh,
        ..options
    };
    let started = Instant::now();
    let base = Design::reference(vec![]);
    let table = RodTable::compute(&base, &VariableBounds::default(), &options, 2, &|| false)
        .expect("the table's balloons solve");
    let fits = &table.fit_mm;
    let worst_fit = fits.iter().copied().fold(0.0, f64::max);
    println!(
        "rod table: {} patches in {:.1} s (2 threads), fit to FE median {:.2} mm, worst {worst_fit:.2} mm",
        fits.len(),
        started.elapsed().as_secs_f64(),
        median(fits.clone())
    );
    let mut rng = SeededRng::new(1);
    let mut sets: Vec<(String, Vec<Design>)> = (curves().into_iter())
        .map(|(name, curve)| (name, designs(&curve, count, &mut rng, false)))
        .collect();
    sets.push(("round trips".into(), round_trip_designs(10, 1)));
    let header: Vec<String> = scales.iter().map(|s| format!("scale {s}")).collect();
    println!(
        "designs | FE ms (median) | table rod ms (median) | search mesh | table rod | {}",
        header.join(" | ")
    );
    let mut all: Vec<Vec<f64>> = vec![Vec::new(); scales.len()];
    let mut all_coarse = Vec::new();
    let mut all_tabled = Vec::new();
    for (name, designs) in &sets {
        let mut fe_ms = Vec::new();
        let mut rod_ms = Vec::new();
        let mut errors: Vec<Vec<f64>> = vec![Vec::new(); scales.len()];
        let mut coarse = Vec::new();
        let mut tabled = Vec::new();
        for design in designs {
            let Ok(fe) = simulate(design, &options) else {
                println!("{name}: a design did not solve");
                continue;
            };
            fe_ms.push(fe.elapsed.as_secs_f64() * 1e3);
            let on_search = simulate(design, &search).map(|s| s.centreline);
            if let Some(e) = on_search
                .ok()
                .and_then(|c| shape_error(&c, &fe.centreline, 200).ok())
            {
                coarse.push(e.percent_of_length);
            }
            let clock = Instant::now();
            let curve = table.centreline(design).expect("a rod centreline");
            rod_ms.push(clock.elapsed().as_secs_f64() * 1e3);
            if let Ok(e) = shape_error(&curve, &fe.centreline, 200) {
                tabled.push(e.percent_of_length);
            }
            for (k, &scale) in scales.iter().enumerate() {
                let Some(curve) = rod(design, scale) else {
                    continue;
                };
                if let Ok(e) = shape_error(&curve, &fe.centreline, 200) {
                    errors[k].push(e.percent_of_length);
                }
            }
        }
        let cells: Vec<String> = (errors.iter().enumerate())
            .map(|(k, e)| {
                all[k].extend(e);
                summary(e)
            })
            .collect();
        println!(
            "{name} ({}) | {:.0} | {:.3} | {} | {} | {}",
            designs.len(),
            median(fe_ms),
            median(rod_ms),
            summary(&coarse),
            summary(&tabled),
            cells.join(" | ")
        );
        all_coarse.extend(coarse);
        all_tabled.extend(tabled);
    }
    let medians: Vec<String> = all
        .into_iter()
        .map(|v| format!("{:.1} %", median(v)))
        .collect();
    println!(
        "all | | | {} | {} | {}",
        summary(&all_coarse),
        summary(&all_tabled),
        medians.join(" | ")
    );
}
