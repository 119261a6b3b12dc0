//! The spread of each design.json's design (`spread::linear_spread` at the
//! default tolerances, one thread) on the meshes it could be computed on:
//! the default mesh, the verification model (graded 1 mm), coarser ones,
//! and the spread stage's pair (the balloon's sources on graded 1 mm, the
//! patches' on graded 2 mm); each row the RMS spread (mm), its ratio to
//! the default mesh's, its wall time and its three largest contributors.
//!
//! `cargo run --release -p patchwork-core --example spread_models -- DESIGN.json…`

use std::time::Instant;

use patchwork_core::fe::SimulateOptions;
use patchwork_core::fe::mesh::MeshSpec;
use patchwork_core::inverse::Fidelity;
use patchwork_core::spread::{Tolerances, linear_spread};

#[path = "common/design_json.rs"]
mod design_json;

/// The default mesh first: the others' spreads are read against it. Each
/// row's mesh, and the patches' mesh where it differs.
fn meshes(radius_mm: f64) -> Vec<(&'static str, MeshSpec, Option<MeshSpec>)> {
    let draft = Fidelity::Draft.tuning(radius_mm);
    let verify = MeshSpec::graded(1.0, 4.0);
    vec![
        (
            "graded 0.5 / 4 mm (default)",
            MeshSpec::default_simulation(),
            None,
        ),
        ("graded 1 / 4 mm (verification)", verify, None),
        ("graded 1.5 / 4.5 mm", MeshSpec::graded(1.5, 4.5), None),
        ("graded 2 / 6 mm", MeshSpec::graded(2.0, 6.0), None),
        ("draft's search model", draft.search_mesh, None),
        (
            "the spread stage's (patches on graded 2 / 6 mm)",
            verify,
            draft.spread_patch_mesh,
        ),
    ]
}

fn main() {
    println!("| design | mesh | spread mm | / default | s | largest three (mm) |");
    println!("|---|---|---|---|---|---|");
    for path in std::env::args().skip(1) {
        let design = design_json::design_of(&path);
        let mut default = None;
        let rows = meshes(design.balloon.radius_mm);
        for (i, (name, mesh, patch_mesh)) in rows.into_iter().enumerate() {
            let model = |mesh| SimulateOptions {
                mesh,
                ..SimulateOptions::default()
            };
            let (options, patch_model) = (model(mesh), patch_mesh.map(model));
            let models = (&options, patch_model.as_ref());
            let started = Instant::now();
            let spread = linear_spread(&design, None, &Tolerances::default(), models, 1, None);
            let seconds = started.elapsed().as_secs_f64();
            let spread = match spread {
                Ok(spread) => spread,
                Err(e) => {
                    println!("| {path} | {name} | failed: {e} | | {seconds:.1} | |");
                    continue;
                }
            };
            if i == 0 {
                default = Some(spread.rms_mm);
            }
            // Against the default mesh's spread only (none where it failed).
            let ratio = default.map_or("–".to_string(), |d| format!("{:.3}", spread.rms_mm / d));
            let largest: Vec<String> = (spread.contributors.iter().take(3))
                .map(|c| format!("{} {:.2}", c.label, c.rms_mm))
                .collect();
            println!(
                "| {path} | {name} | {:.2} | {ratio} | {seconds:.1} | {} |",
                spread.rms_mm,
                largest.join(", ")
            );
        }
    }
}
