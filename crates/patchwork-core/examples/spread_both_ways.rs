//! The spread read one way against both ways, checked by Monte-Carlo: each
//! design.json's design on the spread's model (graded 1 mm), every source
//! solved at +tolerance and at −tolerance (the second from the nominal and
//! from the nominal reflected through the first, `fe::reflected_start`:
//! Newton iterations of each), and four figures of the centreline's RMS
//! spread against a Monte-Carlo check of `MC` samples (default 200, seed 1):
//! every source one way (|d₊|²), every source both ways (|a|² + 3|b|²
//! each), the same with the mean moves added as vectors, and `spread_of`
//! itself (the large sources both ways, the rest linearised).
//!
//! `MC=200 cargo run --release -p patchwork-core --example spread_both_ways -- DESIGN.json…`

use std::sync::atomic::AtomicBool;

use patchwork_core::curve::{Curve, Point};
use patchwork_core::design::Design;
use patchwork_core::fe::mesh::MeshSpec;
use patchwork_core::fe::newton::PatternCache;
use patchwork_core::fe::{SimulateOptions, Simulation, reflected_start, simulate, simulate_with};
use patchwork_core::spread::{
    Against, Change, Models, Nominal, Source, Tolerances, monte_carlo, offsets_of, spread_of,
};

#[path = "common/design_json.rs"]
mod design_json;

const SAMPLES: usize = 64;

/// Sums over the sources of one design, per sample where it says so.
#[derive(Default)]
struct Sums {
    one_way: f64,
    both_ways: f64,
    scatter: f64,
    mean: Vec<Point>,
    iterations: [usize; 3],
}

/// One source: its solves and its terms added to `sums`, each source's
/// read as the spread reads it (`spread::Change`).
fn source(source: &Source, design: &Design, nominal: &Nominal, samples: &Curve, sums: &mut Sums) {
    let tolerance = source.tolerance(&Tolerances::default()).0;
    let options = nominal.source_options();
    let solve = |delta: f64, start: &Simulation| {
        simulate_with(
            &source.moved(design, delta),
            &options,
            Some(start),
            nominal.patterns,
        )
        .expect("a moved design inflates")
    };
    let plus = solve(tolerance, nominal.simulation);
    let minus = solve(-tolerance, nominal.simulation);
    let reflected = reflected_start(nominal.simulation, &plus).expect("the same balloon");
    let minus_reflected = solve(-tolerance, &reflected);
    let its = [&plus, &minus, &minus_reflected].map(|s| s.stats.iterations);
    let home = &nominal.simulation.centreline;
    let offsets = |s: &Simulation| offsets_of(&s.centreline, home, samples).expect("a centreline");
    let (p, m) = (offsets(&plus), offsets(&minus));
    let both = Change::both_ways(&p, &m);
    let n = SAMPLES as f64;
    let shift_sq: f64 = both.shift.iter().map(|b| b.norm_squared()).sum();
    let [one, other] = [&p, &m].map(|o| Change::one_way(o).samples_sq() / n);
    let both_sq = both.samples_sq() / n;
    for (total, b) in sums.mean.iter_mut().zip(&both.shift) {
        *total += b;
    }
    println!(
        "{} | {:.3} | {:.3} | {:.3} | {} | {} | {}",
        source.label(),
        one.sqrt(),
        other.sqrt(),
        both_sq.sqrt(),
        its[0],
        its[1],
        its[2]
    );
    sums.one_way += one;
    sums.both_ways += both_sq;
    sums.scatter += both_sq - shift_sq / n;
    for (total, k) in sums.iterations.iter_mut().zip(its) {
        *total += k;
    }
}

fn main() {
    let samples_mc: usize = std::env::var("MC").map_or(200, |v| v.parse().expect("MC: a count"));
    let options = SimulateOptions {
        mesh: MeshSpec::graded(1.0, 4.0),
        ..SimulateOptions::default()
    };
    let tolerances = Tolerances::default();
    for path in std::env::args().skip(1) {
        let design = design_json::design_of(&path);
        let simulation = simulate(&design, &options).expect("the design inflates");
        let samples = simulation.centreline.resample(SAMPLES).expect("samples");
        let patterns = PatternCache::default();
        let nominal = Nominal {
            design: &design,
            simulation: &simulation,
            options: &options,
            patterns: &patterns,
        };
        println!(
            "\n{path}\nsource | +δ mm | −δ mm | both ways mm | its +δ | −δ from nominal | −δ reflected"
        );
        let mut sums = Sums {
            mean: vec![Point::zeros(); SAMPLES],
            ..Sums::default()
        };
        for s in Source::all(&design, &tolerances) {
            source(&s, &design, &nominal, &samples, &mut sums);
        }
        let mean_sq = sums.mean.iter().map(|b| b.norm_squared()).sum::<f64>() / SAMPLES as f64;
        let together = (sums.scatter + mean_sq).sqrt();
        let against = Against::target(&simulation, None).expect("a centreline");
        let spread = spread_of(&Models::one(nominal), &against, &tolerances, 1).expect("a spread");
        let check = monte_carlo(
            &nominal,
            &spread,
            &tolerances,
            (samples_mc, 1),
            1,
            &AtomicBool::new(false),
        );
        let [a, b, c, d] = [
            sums.one_way.sqrt(),
            sums.both_ways.sqrt(),
            together,
            spread.rms_mm,
        ];
        let mc = check.rms_mm;
        println!(
            "{path}: Monte-Carlo ({samples_mc}, {} failed) {mc:.3} mm over: one way {:.3}, \
             both ways {:.3}, with the mean moves {:.3}, spread_of {:.3} ({} solves); \
             iterations +δ {}, −δ from the nominal {}, from the reflection {}",
            check.failed,
            mc / a,
            mc / b,
            mc / c,
            mc / d,
            spread.solves,
            sums.iterations[0],
            sums.iterations[1],
            sums.iterations[2]
        );
    }
}
