//! How well the linearised response (`fe::sensitivity`) stands in for the
//! spread's solves, source by source: each design.json's design on the
//! spread's model (graded 1 mm), each source at its default tolerance, its
//! centreline's change from the nominal (aligned, RMS over the samples, as
//! the spread measures it) by a Newton solve warm-started from the nominal
//! (what `spread_of` does) and by the linearised response; their ratio per
//! kind of source, and each way's time.
//!
//! `cargo run --release -p patchwork-core --example spread_linearised -- DESIGN.json…`

use std::time::Instant;

use patchwork_core::curve::{AlignedSamples, Curve};
use patchwork_core::design::Design;
use patchwork_core::fe::mesh::MeshSpec;
use patchwork_core::fe::newton::PatternCache;
use patchwork_core::fe::sensitivity::linearised_centrelines;
use patchwork_core::fe::{SimulateOptions, simulate, simulate_with};
use patchwork_core::spread::{Nominal, Source, Tolerances};

#[path = "common/design_json.rs"]
mod design_json;

const SAMPLES: usize = 64;

/// RMS (mm) of `moved`'s change from the nominal samples after alignment.
fn rms_change(moved: &Curve, samples: &Curve) -> f64 {
    let aligned = AlignedSamples::new(moved, samples).expect("a centreline");
    let sum: f64 = aligned.residuals.iter().map(|r| r.norm_squared()).sum();
    (sum / SAMPLES as f64).sqrt()
}

fn kind(source: &Source) -> String {
    match source {
        Source::Patch { quantity, .. } => format!("{quantity:?}"),
        other => format!("{other:?}"),
    }
}

fn main() {
    let options = SimulateOptions {
        mesh: MeshSpec::graded(1.0, 4.0),
        ..SimulateOptions::default()
    };
    let tolerances = Tolerances::default();
    let threads = 1;
    println!("design | source | solved mm | linearised mm | ratio");
    let mut ratios: std::collections::BTreeMap<String, Vec<f64>> = Default::default();
    for path in std::env::args().skip(1) {
        let design = design_json::design_of(&path);
        let nominal_sim = simulate(&design, &options).expect("the design inflates");
        let samples = nominal_sim.centreline.resample(SAMPLES).expect("samples");
        let patterns = PatternCache::default();
        let nominal = Nominal {
            design: &design,
            simulation: &nominal_sim,
            options: &options,
            patterns: &patterns,
        };
        let sources = Source::all(&design, &tolerances);
        let moved: Vec<Design> = sources
            .iter()
            .map(|s| s.moved(&design, s.tolerance(&tolerances).0))
            .collect();
        let started = Instant::now();
        let source_options = nominal.source_options();
        let solved: Vec<f64> = moved
            .iter()
            .map(|d| {
                let sim = simulate_with(d, &source_options, Some(&nominal_sim), &patterns)
                    .expect("a moved design inflates");
                rms_change(&sim.centreline, &samples)
            })
            .collect();
        let solve_s = started.elapsed().as_secs_f64();
        let started = Instant::now();
        let linear =
            linearised_centrelines(&design, &nominal_sim, &options, &moved, threads, &patterns)
                .expect("a stable nominal state");
        let linear_s = started.elapsed().as_secs_f64();
        for ((source, s), l) in sources.iter().zip(&solved).zip(&linear) {
            let l = l.as_ref().map_or(f64::NAN, |c| rms_change(c, &samples));
            println!(
                "{path} | {} | {s:.4} | {l:.4} | {:.3}",
                source.label(),
                l / s
            );
            if *s > 1e-3 {
                ratios.entry(kind(source)).or_default().push(l / s);
            }
        }
        println!(
            "{path}: {} sources; solved {solve_s:.1} s, linearised {linear_s:.1} s ({threads} threads)",
            sources.len()
        );
    }
    println!("\nkind | n | linearised / solved: min, median, max");
    for (kind, mut r) in ratios {
        r.sort_by(f64::total_cmp);
        println!(
            "{kind} | {} | {:.3}, {:.3}, {:.3}",
            r.len(),
            r[0],
            r[r.len() / 2],
            r[r.len() - 1]
        );
    }
}
