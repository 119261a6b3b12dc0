//! One material evaluation — energy alone (the line search's) and energy with
//! stress and tangent (assembly's) — for the reference balloon and patch,
//! incompressible and at K₀/μ₀ = 20 (the authors' ABAQUS/Explicit balloon,
//! whose thickness is solved from σ₃₃ = 0 at every evaluation), over in-plane
//! states from the unstrained one to the compressible tube's (hoop 5.2,
//! axial 3.7) with shear.
//!
//! `cargo bench -p patchwork-core --bench material`

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use patchwork_core::material::{Compressibility, Material};

/// 64 in-plane C states up to c₁₁ ≈ 27, c₂₂ ≈ 13.5.
fn states() -> Vec<[f64; 3]> {
    (0..64)
        .map(|i| {
            let t = i as f64 / 63.0;
            [1.0 + 26.0 * t, 1.0 + 12.5 * t * t, 0.3 * t * (1.0 - t)]
        })
        .collect()
}

fn bench(c: &mut Criterion) {
    let states = states();
    let mut group = c.benchmark_group("material (64 states)");
    for (name, material) in [
        ("balloon", Material::reference_balloon()),
        ("patch", Material::reference_patch()),
    ] {
        for (label, compressibility) in [
            ("incompressible", Compressibility::Incompressible),
            ("K0/mu0 = 20", Compressibility::abaqus_explicit()),
        ] {
            let m = material.clone().with_compressibility(compressibility);
            group.bench_function(format!("{name} {label}: energy"), |b| {
                b.iter(|| states.iter().map(|s| m.energy(black_box(*s))).sum::<f64>())
            });
            group.bench_function(format!("{name} {label}: stress and tangent"), |b| {
                b.iter(|| {
                    states
                        .iter()
                        .map(|s| m.response(black_box(*s)).hessian[0][0])
                        .sum::<f64>()
                })
            });
        }
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
