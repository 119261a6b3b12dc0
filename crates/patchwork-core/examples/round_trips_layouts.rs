//! Round trips with an unknown layout: ten seeded random feasible designs of
//! 4–12 patches on a 400 mm balloon — single patches and trains of 2–5
//! adjacent patches 2–4 mm apart whose widths and angles are graded along
//! the train and whose X follows the inclined patches round the tube (the
//! first trip a five-patch train at 20–30°, which makes a helix) — simulated
//! on draft's finest model, then designed from the centreline alone with
//! `draft` as users get it (the count is not given). Prints the table in
//! BENCHMARKS.md. About ten minutes:
//! `cargo run --release -p patchwork-core --example round_trips_layouts`
//!
//! `trips=N` runs fewer; `fidelity=standard` another preset.

use std::sync::atomic::AtomicBool;

use patchwork_core::cmaes::SeededRng;
use patchwork_core::design::{Balloon, Design, Patch};
use patchwork_core::fe::{SimulateOptions, simulate};
use patchwork_core::inverse::{Fidelity, Plan, TuningOverrides, UserSettings, design};

const BALLOON_MM: f64 = 400.0;

/// A random layout of 4–12 patches, every one within the default bounds.
fn layout(rng: &mut SeededRng, helix_first: bool) -> Vec<Patch> {
    let mut between = |lo: f64, hi: f64| lo + (hi - lo) * rng.uniform();
    let circumference = Balloon::default().circumference();
    let wanted = between(4.0, 12.99) as usize;
    let mut patches = Vec::new();
    let mut y = between(15.0, 30.0);
    let mut first = true;
    while patches.len() < wanted {
        let room = wanted - patches.len();
        let count = match (first && helix_first, between(0.0, 1.0) < 0.4) {
            (true, _) => 5,
            (false, true) => 1,
            (false, false) => between(2.0, 5.99).min(room as f64) as usize,
        };
        let (h, gap) = (between(12.0, 28.0), between(2.0, 4.0));
        let (w0, w1) = (between(1.2, 3.0), between(1.2, 3.0));
        let (t0, t1) = match first && helix_first {
            true => (between(20.0, 30.0), between(20.0, 30.0)),
            false => (between(-35.0, 35.0), between(-35.0, 35.0)),
        };
        let mut x = between(0.0, circumference);
        for i in 0..count {
            let f = if count > 1 {
                i as f64 / (count - 1) as f64
            } else {
                0.0
            };
            let theta: f64 = t0 + f * (t1 - t0);
            if y + h > BALLOON_MM - 10.0 {
                return patches;
            }
            patches.push(Patch {
                x_mm: x.rem_euclid(circumference),
                y_mm: y + 0.5 * h,
                h_mm: h,
                w_mm: w0 + f * (w1 - w0),
                theta_deg: theta,
            });
            // The next patch of the train starts where this one's end went
            // round the tube.
            x += (h + gap) * theta.to_radians().tan();
            y += h + gap;
        }
        y += between(15.0, 40.0);
        first = false;
    }
    patches
}

fn main() {
    let mut trips = 10;
    let mut fidelity = Fidelity::Draft;
    for arg in std::env::args().skip(1) {
        match arg.split_once('=') {
            Some(("trips", n)) => trips = n.parse().expect("a count"),
            Some(("fidelity", f)) => fidelity = f.parse().expect("a fidelity"),
            _ => panic!("unknown argument {arg}"),
        }
    }
    let mut rng = SeededRng::new(2027);
    let mut errors = Vec::new();
    println!("| # | true patches (trains) | designed patches | shape error % | wall s |");
    println!("|---|---|---|---|---|");
    for trip in 1..=trips {
        let patches = layout(&mut rng, trip == 1);
        let truth = Design {
            balloon: Balloon {
                length_mm: BALLOON_MM,
                ..Balloon::default()
            },
            ..Design::reference(patches.clone())
        };
        truth.validate().expect("a valid design");
        let settings = UserSettings {
            base: Design {
                patches: vec![],
                ..truth.clone()
            },
            fidelity,
            seed: trip,
            threads: 2,
            ..UserSettings::default()
        };
        let plan = Plan::resolve(settings, &TuningOverrides::default()).expect("valid");
        let tuning = plan.tuning();
        let model = SimulateOptions {
            mesh: tuning.correction_mesh.unwrap_or(tuning.verify_mesh),
            ..SimulateOptions::default()
        };
        let target = simulate(&truth, &model)
            .expect("a feasible design")
            .centreline;
        let outcome = design(&target, &plan, &AtomicBool::new(false), &mut |_| {})
            .expect("the round trip designs");
        let trains = describe(&patches);
        println!(
            "| {trip} | {} ({trains}) | {} | {:.2} | {:.1} |",
            patches.len(),
            outcome.design.patches.len(),
            outcome.metrics.shape_error_percent,
            outcome.elapsed.as_secs_f64()
        );
        errors.push(outcome.metrics.shape_error_percent);
    }
    errors.sort_by(f64::total_cmp);
    let n = errors.len();
    println!(
        "median shape error {:.2} %, worst {:.2} %",
        (errors[(n - 1) / 2] + errors[n / 2]) / 2.0,
        errors[n - 1]
    );
}

/// The layout's groups of adjacent patches (less than 5 mm apart), as
/// their sizes: "5+1+3".
fn describe(patches: &[Patch]) -> String {
    let mut groups: Vec<usize> = Vec::new();
    for pair in std::iter::once(None)
        .chain(patches.windows(2).map(Some))
        .collect::<Vec<_>>()
    {
        match pair {
            Some(p) if p[1].y_mm - 0.5 * p[1].h_mm - (p[0].y_mm + 0.5 * p[0].h_mm) < 5.0 => {
                *groups.last_mut().expect("a group") += 1
            }
            _ => groups.push(1),
        }
    }
    groups
        .iter()
        .map(|g| g.to_string())
        .collect::<Vec<_>>()
        .join("+")
}
