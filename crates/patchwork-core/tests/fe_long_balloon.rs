//! A long balloon's cold solve: 1 m uninflated with 30 patches (about 3.1 m
//! inflated), on the default simulation mesh. Its soft modes are slightly
//! concave at the iterates; the cold starts' lower shift floor lets Newton
//! cross them, so the solve converges from its starts (no continuation in
//! patch stiffness) in about a hundred iterations (docs/studies.md, "A 1 m,
//! 30-patch balloon's cold solve").

use patchwork_core::design::scenes::long_balloon;
use patchwork_core::fe::mesh::MeshSpec;
use patchwork_core::fe::{SimulateOptions, simulate};

#[test]
fn a_one_metre_balloon_with_thirty_patches_converges_from_its_starts() {
    let options = SimulateOptions {
        mesh: MeshSpec::default_simulation(),
        threads: patchwork_core::available_cores().min(2),
        ..SimulateOptions::default()
    };
    let sim = simulate(&long_balloon(), &options).expect("the long balloon solves");
    println!(
        "{} Newton iterations, {} solves, {:.1} s, {:.1} mm inflated",
        sim.stats.iterations,
        sim.continuation_steps,
        sim.elapsed.as_secs_f64(),
        sim.inflated_length_mm
    );
    assert!(sim.stats.stable, "not a stable state");
    assert_eq!(sim.continuation_steps, 1, "continuation took over");
    assert!(
        sim.stats.iterations <= 150,
        "{} Newton iterations",
        sim.stats.iterations
    );
    // The bare tube's axial stretch is 3.67 (membrane theory, DESIGN.md);
    // the patches shorten their 450 mm of it.
    assert!(
        (2900.0..3300.0).contains(&sim.inflated_length_mm),
        "{} mm inflated",
        sim.inflated_length_mm
    );
}
