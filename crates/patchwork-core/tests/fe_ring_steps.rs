//! Newton's steps taken ring by ring (`Steps::Rings`) end at the same
//! equilibrium as linear steps: a two-patch balloon bent by 90° and more,
//! each of three moved designs warm-started from its state, solved both
//! ways to the default tolerance (1e-9 of the pressure load).
//!
//! Tolerance: the centrelines' corresponding ring centres within 1e-4 mm
//! (the residual tolerance leaves displacements along the tube's
//! soft swing of about 1e-5 mm; the two rules' iterates stop at different
//! points within it).

use patchwork_core::design::{Balloon, Design, Patch};
use patchwork_core::fe::mesh::MeshSpec;
use patchwork_core::fe::newton::{PatternCache, Steps};
use patchwork_core::fe::{SimulateOptions, Simulation, simulate, simulate_with};

fn design() -> Design {
    let patch = |y_mm: f64, theta_deg: f64| Patch {
        x_mm: 0.0,
        y_mm,
        h_mm: 20.0,
        w_mm: 2.5,
        theta_deg,
    };
    Design {
        balloon: Balloon {
            length_mm: 100.0,
            ..Balloon::default()
        },
        ..Design::reference(vec![patch(25.0, 0.0), patch(65.0, 15.0)])
    }
}

fn options(steps: Steps) -> SimulateOptions {
    let mut options = SimulateOptions {
        mesh: MeshSpec::graded(1.0, 4.0),
        threads: 1,
        ..SimulateOptions::default()
    };
    options.newton.steps = steps;
    options
}

#[test]
fn ring_steps_end_where_linear_steps_do() {
    let nominal = design();
    let start = simulate(&nominal, &options(Steps::Linear)).expect("the design inflates");
    let tip = |s: &Simulation| *s.centreline.points().last().expect("a tip");
    let mut wider = nominal.clone();
    wider.patches[1].w_mm += 1.0;
    let mut turned = nominal.clone();
    turned.patches[0].x_mm += 2.0;
    let mut harder = nominal.clone();
    harder.pressure_kpa += 0.5;
    let patterns = PatternCache::default();
    for (name, moved) in [("wider", wider), ("turned", turned), ("pressure", harder)] {
        let [linear, rings] = [Steps::Linear, Steps::Rings].map(|steps| {
            simulate_with(&moved, &options(steps), Some(&start), &patterns)
                .unwrap_or_else(|e| panic!("{name}, {steps:?}: {e}"))
        });
        let swing = (tip(&linear) - tip(&start)).norm();
        let gap = linear.centreline.largest_gap(&rings.centreline);
        println!(
            "{name}: tip moves {swing:.2} mm; Newton iterations {} linear, {} rings; apart {gap:.1e} mm",
            linear.stats.iterations, rings.stats.iterations
        );
        assert!(swing > 1.0, "{name}: the tip moves only {swing} mm");
        assert!(gap < 1e-4, "{name}: the centrelines are {gap} mm apart");
    }
}
