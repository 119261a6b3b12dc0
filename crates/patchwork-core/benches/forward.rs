//! Forward solve of the reference scene with the six KSA patches of the
//! Hilbert curve (DESIGN.md), 20 kPa: cold start at 2 mm and 1 mm elements —
//! with the mesh's tangent pattern cached from an earlier solve, as in a design
//! search, and on a new mesh (ordering and symbolic factorisation included) —
//! and warm start from a nearby design (as in a CMA-ES generation) at 2 mm.
//!
//! `cargo bench -p patchwork-core --bench forward`

use criterion::{Criterion, criterion_group, criterion_main};
use patchwork_core::curve::ReferenceCurve;
use patchwork_core::design::{Design, Patch};
use patchwork_core::fe::mesh::MeshSpec;
use patchwork_core::fe::newton::PatternCache;
use patchwork_core::fe::{SimulateOptions, simulate_from, simulate_with};
use patchwork_core::ksa::{KsaParams, ksa};

fn hilbert_design() -> Design {
    let seed = ksa(&ReferenceCurve::Hilbert.curve(), &KsaParams::default()).expect("valid");
    Design::reference(seed.patches)
}

/// A candidate a CMA-ES step away: every patch moved by a fraction of a mm/degree.
fn neighbour(design: &Design) -> Design {
    let patches = design
        .patches
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let s = if i % 2 == 0 { 1.0 } else { -1.0 };
            Patch {
                x_mm: p.x_mm + 0.3 * s,
                y_mm: p.y_mm + 0.5 * s,
                h_mm: p.h_mm - 0.4 * s,
                w_mm: p.w_mm + 0.1,
                theta_deg: p.theta_deg + 2.0 * s,
            }
        })
        .collect();
    Design {
        patches,
        ..design.clone()
    }
}

fn bench(c: &mut Criterion) {
    let design = hilbert_design();
    let mut group = c.benchmark_group("forward_hilbert_6_patches");
    group.sample_size(10);
    for h in [2.0, 1.0] {
        let options = SimulateOptions {
            mesh: MeshSpec::uniform(h),
            ..SimulateOptions::default()
        };
        let patterns = PatternCache::default();
        group.bench_function(format!("cold_{h}mm"), |b| {
            b.iter(|| simulate_with(&design, &options, None, &patterns).expect("converges"))
        });
        group.bench_function(format!("cold_{h}mm_new_mesh"), |b| {
            b.iter(|| simulate_from(&design, &options, None).expect("converges"))
        });
    }
    let options = SimulateOptions::default();
    let patterns = PatternCache::default();
    let converged = simulate_with(&design, &options, None, &patterns).expect("converges");
    let candidate = neighbour(&design);
    group.bench_function("warm_2mm", |b| {
        b.iter(|| {
            simulate_with(&candidate, &options, Some(&converged), &patterns).expect("converges")
        })
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
