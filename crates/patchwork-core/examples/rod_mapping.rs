//! How well the rod, corrected by FE at one design, predicts FE at a nearby
//! one: the search's question each time it scores a candidate on the rod
//! between two corrections. For each of ten curves' KSA seeds and ten
//! random designs of 4–12 patches on a 400 mm balloon (the round trips'
//! generator, seed 1, as `rod_accuracy`), the base: FE on the `draft`
//! verification model at the base and at CMA-ES-sized perturbations of it
//! (σ in the unit cube); the shape error against FE at the perturbation of
//! - the rod alone,
//! - the rod plus the base's gap to FE as an offset of the centreline
//!   (output space mapping),
//! - the rod with each patch's correction fitted at the base
//!   (`rod::fit_corrections`),
//! - that, plus the gap left after it as an offset.
//!
//! `cargo run --release -p patchwork-core --example rod_mapping -- [perturbations] [sigma]`
//! (defaults 2 and 0.1).

#[path = "common/seeds.rs"]
mod seeds;

use std::time::Instant;

use patchwork_core::cmaes::SeededRng;
use patchwork_core::curve::{Curve, Point, shape_error};
use patchwork_core::design::Design;
use patchwork_core::design::random::round_trip_designs;
use patchwork_core::fe::{SimulateOptions, simulate};
use patchwork_core::inverse::{Fidelity, VariableBounds};
use patchwork_core::rod::{Correction, RodTable, fit_corrections};
use seeds::{curves, designs, median, perturbed};

const SAMPLES: usize = 200;

/// `rod` moved by `offset` (both at `SAMPLES` equal fractions of length).
fn shifted(rod: &Curve, offset: &[Point]) -> Curve {
    let rod = rod.resample(SAMPLES).expect("a rod centreline");
    let points = rod.points().iter().zip(offset).map(|(p, d)| p + d);
    Curve::from_points(points.collect()).expect("a centreline")
}

/// `fe` minus `rod` at `SAMPLES` equal fractions of their lengths.
fn gap(fe: &Curve, rod: &Curve) -> Vec<Point> {
    let fe = fe.resample(SAMPLES).expect("FE centreline");
    let rod = rod.resample(SAMPLES).expect("rod centreline");
    fe.points()
        .iter()
        .zip(rod.points())
        .map(|(f, r)| f - r)
        .collect()
}

fn error(a: &Curve, b: &Curve) -> f64 {
    shape_error(a, b, SAMPLES).map_or(f64::NAN, |e| e.percent_of_length)
}

/// The four predictions' errors at each perturbation of `base`.
fn errors(
    table: &RodTable,
    options: &SimulateOptions,
    base: &Design,
    near: &[Design],
    fit_ms: &mut Vec<f64>,
) -> Vec<[f64; 4]> {
    let Ok(at_base) = simulate(base, options) else {
        return Vec::new();
    };
    let rod = table.centreline(base).expect("a rod centreline");
    let offset = gap(&at_base.centreline, &rod);
    let clock = Instant::now();
    let entries = table.entries(base);
    let corrections: Vec<Correction> = fit_corrections(&table.bare, base, &entries, &at_base.rings);
    fit_ms.push(clock.elapsed().as_secs_f64() * 1e3);
    let corrected = table
        .corrected_centreline(base, &corrections)
        .expect("a rod");
    let corrected_offset = gap(&at_base.centreline, &corrected);
    (near.iter())
        .filter_map(|design| {
            let fe = simulate(design, options).ok()?.centreline;
            let rod = table.centreline(design).ok()?;
            let mapped = shifted(&rod, &offset);
            let corrected = table.corrected_centreline(design, &corrections).ok()?;
            let both = shifted(&corrected, &corrected_offset);
            Some([
                error(&rod, &fe),
                error(&mapped, &fe),
                error(&corrected, &fe),
                error(&both, &fe),
            ])
        })
        .collect()
}

fn main() {
    let args: Vec<f64> = (std::env::args().skip(1))
        .map(|a| a.parse().expect("numbers: perturbations sigma"))
        .collect();
    let count = args.first().map_or(2, |c| *c as usize);
    let sigma = args.get(1).copied().unwrap_or(0.1);
    let radius = Design::reference(vec![]).balloon.radius_mm;
    let tuning = Fidelity::Draft.tuning(radius);
    let options = SimulateOptions {
        threads: 2,
        ..tuning.model(tuning.verify_mesh)
    };
    let base = Design::reference(vec![]);
    let table = RodTable::compute(&base, &VariableBounds::default(), &options, 2, &|| false)
        .expect("the table's balloons solve");
    let mut rng = SeededRng::new(1);
    let mut bases: Vec<(String, Design)> = (curves().into_iter())
        .map(|(name, curve)| (name, designs(&curve, 0, &mut rng, false).remove(0)))
        .collect();
    for (k, d) in round_trip_designs(10, 1).into_iter().enumerate() {
        bases.push((format!("random {}", k + 1), d));
    }
    println!(
        "base | patches | rod alone | rod + offset | corrected rod | corrected rod + offset (% of length, median over {count} at sigma {sigma})"
    );
    let (mut all, mut fit_ms) = ([(); 4].map(|_| Vec::new()), Vec::new());
    for (name, base) in &bases {
        let near = perturbed(base, count, sigma, &mut rng);
        let found = errors(&table, &options, base, &near, &mut fit_ms);
        let mut cell = |k: usize| {
            let v: Vec<f64> = found.iter().map(|e| e[k]).collect();
            all[k].extend(v.iter().copied());
            format!("{:.2}", median(v))
        };
        let cells = [cell(0), cell(1), cell(2), cell(3)];
        println!("{name} | {} | {}", base.patches.len(), cells.join(" | "));
    }
    let cells: Vec<String> = all
        .iter()
        .map(|v| format!("{:.2}", median(v.clone())))
        .collect();
    println!("all (median) | | {}", cells.join(" | "));
    println!("fit: median {:.1} ms", median(fit_ms));
}
