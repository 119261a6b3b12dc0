//! Where one forward solve of the Hilbert reference scene spends its time:
//! pattern setup, assembly, numeric factorisation, substitution, line search.
//!
//! `cargo run --release -p patchwork-core --example solve_profile -- [element_mm] [straight_mm] [runs] [average]`
//!
//! `average` models cut elements by area average instead of the laminate (the default).

use std::time::Instant;

use patchwork_core::curve::ReferenceCurve;
use patchwork_core::design::Design;
use patchwork_core::fe::mesh::MeshSpec;
use patchwork_core::fe::section::CutElements;
use patchwork_core::fe::{SimulateOptions, simulate};
use patchwork_core::ksa::{KsaParams, ksa};

fn main() {
    // Numbers are element_mm [straight_mm] [runs]; a word names the cut-element rule.
    let (words, numbers): (Vec<String>, Vec<String>) = std::env::args()
        .skip(1)
        .partition(|a| a.parse::<f64>().is_err());
    let cut_elements: CutElements = words
        .first()
        .map_or(Ok(CutElements::Laminate), |w| w.parse())
        .unwrap_or_else(|e| panic!("{e}"));
    let args: Vec<f64> = numbers
        .iter()
        .map(|a| a.parse().expect("a number"))
        .collect();
    let element = args.first().copied().unwrap_or(2.0);
    let straight = args.get(1).copied().filter(|s| *s > 0.0);
    let runs = args.get(2).copied().unwrap_or(5.0) as usize;
    let seed = ksa(&ReferenceCurve::Hilbert.curve(), &KsaParams::default()).expect("valid");
    let design = Design::reference(seed.patches);
    let mesh = match straight {
        Some(s) => MeshSpec::graded(element, s),
        None => MeshSpec::uniform(element),
    };
    let options = SimulateOptions {
        mesh,
        cut_elements,
        ..SimulateOptions::default()
    };
    println!(
        "run | total ms | its | factorisations | setup ms | assembly ms | factor ms (per) | substitution ms | line search ms | rest ms"
    );
    for run in 1..=runs {
        let t = Instant::now();
        let sim = simulate(&design, &options).expect("converges");
        let total = t.elapsed().as_secs_f64() * 1e3;
        let s = &sim.stats;
        let ms = |d: std::time::Duration| d.as_secs_f64() * 1e3;
        let accounted = ms(s.setup_time)
            + ms(s.assembly_time)
            + ms(s.factor_time)
            + ms(s.substitution_time)
            + ms(s.line_search_time);
        println!(
            "{run} | {total:.1} | {} | {} | {:.1} | {:.1} | {:.1} ({:.2}) | {:.1} | {:.1} | {:.1}",
            s.iterations,
            s.factorisations,
            ms(s.setup_time),
            ms(s.assembly_time),
            ms(s.factor_time),
            ms(s.factor_time) / s.factorisations.max(1) as f64,
            ms(s.substitution_time),
            ms(s.line_search_time),
            total - accounted,
        );
    }
}
