//! One material evaluation — energy alone (the line search's) and energy with
//! stress and tangent (assembly's) — for the reference balloon and patch,
//! incompressible and at K₀/μ₀ = 20 (the authors' ABAQUS/Explicit balloon,
//! whose thickness is solved from σ₃₃ = 0 at every evaluation), over in-plane
//! states from the unstrained one to the compressible tube's (hoop 5.2,
//! axial 3.7) with shear.
//!
//! The bare tube's state (`fe::tube_theory::inflate_tube`) of the
//! compressible reference balloon, found afresh: a design whose pressure,
//! wall or modulus differs from the last sixteen asked (the spread's
//! balloon sources, each Monte-Carlo sample) pays this once before its
//! solve.
//!
//! `cargo bench -p patchwork-core --bench material`

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use patchwork_core::fe::tube_theory::inflate_tube;
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

/// `inflate_tube` at 24 pressures in turn around 20 kPa, more than the 16
/// states it keeps, so that every call scans.
fn tube_state(c: &mut Criterion) {
    let balloon = Material::reference_balloon();
    let pressures: Vec<f64> = (0..24).map(|i| 0.019 + 0.0001 * i as f64).collect();
    let mut next = 0;
    c.bench_function("tube state: compressible balloon, found afresh", |b| {
        b.iter(|| {
            next = (next + 1) % pressures.len();
            inflate_tube(&balloon, black_box(pressures[next]), 3.18, 0.183)
        })
    });
}

criterion_group!(benches, bench, tube_state);
criterion_main!(benches);
