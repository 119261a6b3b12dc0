//! The balloon's sources (wall, modulus, pressure) as one variable on the
//! verification model, as `spread/balloon.rs` finds them: each source's
//! size along the largest one's linearised field and the cosine between
//! them; the joint RMS move from the three-point and the five-point
//! Gauss–Hermite rules and from a dense integral over the normal (g at
//! every 0.25 σ to ±4.5 σ). `wall` takes the wall alone.
//!
//! `cargo run --release -p patchwork-core --example balloon_together -- [wall] DESIGN.json…`

use std::f64::consts::PI;

use patchwork_core::curve::{Curve, Point};
use patchwork_core::design::Design;
use patchwork_core::fe::newton::PatternCache;
use patchwork_core::fe::sensitivity::linearised_centrelines;
use patchwork_core::fe::{SimulateOptions, Simulation, simulate_with};
use patchwork_core::inverse::Fidelity;
use patchwork_core::spread::{Nominal, Source, Tolerances, offsets_of};

#[path = "common/design_json.rs"]
mod design_json;

/// The samples of the centreline compared.
const SAMPLES: usize = 64;

fn main() {
    let (words, paths): (Vec<String>, Vec<String>) =
        std::env::args().skip(1).partition(|a| a == "wall");
    let sources = match words.is_empty() {
        true => vec![Source::Wall, Source::Modulus, Source::Pressure],
        false => vec![Source::Wall],
    };
    for path in paths {
        let design = design_json::design_of(&path);
        let tuning = Fidelity::Draft.tuning(design.balloon.radius_mm);
        let options = SimulateOptions {
            threads: 2,
            ..tuning.model(tuning.verify_mesh)
        };
        let patterns = PatternCache::default();
        let nominal = simulate_with(&design, &options, None, &patterns).expect("solves");
        let samples = nominal.centreline.resample(SAMPLES).expect("a centreline");
        let at = Along::new(&design, &nominal, (&options, &patterns), &sources, &samples);
        println!(
            "{path}: sizes (mm) {:?}, cosines {:?}",
            at.sizes(),
            at.cosines
        );
        let rule = |nodes: &[(f64, f64)]| {
            let sum: f64 = (nodes.iter())
                .map(|&(x, w)| w * (at.mean_sq(x) + at.mean_sq(-x)))
                .sum();
            sum.sqrt()
        };
        println!("  3 points: {:.3} mm", rule(&[(3f64.sqrt(), 1.0 / 6.0)]));
        let five = [(1.355_626_18, 0.222_075_922), (2.856_970_01, 0.011_257_411)];
        println!("  5 points: {:.3} mm", rule(&five));
        let dense: f64 = (-18..=18)
            .filter(|&i| i != 0)
            .map(|i| {
                let x = 0.25 * f64::from(i);
                at.mean_sq(x) * (-x * x / 2.0).exp() / (2.0 * PI).sqrt() * 0.25
            })
            .sum();
        println!("  dense:    {:.3} mm", dense.sqrt());
    }
}

/// The joint variable of `sources` on one nominal state.
struct Along<'a> {
    design: &'a Design,
    nominal: &'a Simulation,
    options: SimulateOptions,
    patterns: &'a PatternCache,
    samples: &'a Curve,
    sources: &'a [Source],
    /// Each source's signed size along the largest one's field (mm RMS).
    c: Vec<f64>,
    cosines: Vec<f64>,
}

impl<'a> Along<'a> {
    fn new(
        design: &'a Design,
        nominal: &'a Simulation,
        (options, patterns): (&SimulateOptions, &'a PatternCache),
        sources: &'a [Source],
        samples: &'a Curve,
    ) -> Along<'a> {
        let t = Tolerances::default();
        let moved: Vec<Design> = (sources.iter())
            .map(|s| s.moved(design, s.tolerance(&t).0))
            .collect();
        let lines = linearised_centrelines(design, nominal, options, &moved, 2, patterns);
        let fields: Vec<Vec<Point>> = (lines.expect("linearised").iter())
            .map(|c| {
                let c = c.as_ref().expect("a linearised centreline");
                offsets_of(c, &nominal.centreline, samples)
                    .expect("offsets")
                    .residuals
            })
            .collect();
        let dot = |a: &[Point], b: &[Point]| a.iter().zip(b).map(|(x, y)| x.dot(y)).sum::<f64>();
        let largest = (fields.iter())
            .max_by(|a, b| dot(a, a).total_cmp(&dot(b, b)))
            .expect("a source");
        let norm = dot(largest, largest).sqrt();
        let along: Vec<f64> = fields.iter().map(|f| dot(f, largest) / norm).collect();
        let cosines = (fields.iter().zip(&along))
            .map(|(f, a)| a / dot(f, f).sqrt())
            .collect();
        let spread = Nominal {
            design,
            simulation: nominal,
            options,
            patterns,
        };
        Along {
            design,
            nominal,
            options: spread.source_options(),
            patterns,
            samples,
            sources,
            c: along.iter().map(|a| a / (SAMPLES as f64).sqrt()).collect(),
            cosines,
        }
    }

    fn sizes(&self) -> Vec<f64> {
        self.c.iter().map(|c| (c * 100.0).round() / 100.0).collect()
    }

    /// The mean square move of the samples (mm²) with every source at
    /// x cₖ/σ of its tolerance.
    fn mean_sq(&self, x: f64) -> f64 {
        let t = Tolerances::default();
        let sigma = self.c.iter().map(|c| c * c).sum::<f64>().sqrt();
        let design = (self.sources.iter().zip(&self.c)).fold(self.design.clone(), |d, (s, c)| {
            s.moved(&d, x * c / sigma * s.tolerance(&t).0)
        });
        let solved = simulate_with(&design, &self.options, Some(self.nominal), self.patterns)
            .expect("solves");
        let moved = offsets_of(&solved.centreline, &self.nominal.centreline, self.samples);
        let residuals = moved.expect("offsets").residuals;
        residuals.iter().map(|r| r.norm_squared()).sum::<f64>() / SAMPLES as f64
    }
}
