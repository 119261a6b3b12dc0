//! Curve analysis and KSA on a 10 000-point curve (goal: under 10 ms).
//!
//! `cargo bench -p patchwork-core --bench curve_ksa`

use criterion::{Criterion, criterion_group, criterion_main};
use patchwork_core::curve::{AnalysisOptions, ReferenceCurve, Units, analyse, read_text};
use patchwork_core::ksa::{KsaParams, ksa};
use std::hint::black_box;

fn bench(c: &mut Criterion) {
    let curve = ReferenceCurve::Hilbert
        .curve()
        .resample(10_000)
        .expect("valid");
    let csv: String = curve
        .points()
        .iter()
        .map(|p| format!("{},{},{}\n", p.x, p.y, p.z))
        .collect();
    let params = KsaParams::default();
    let mut group = c.benchmark_group("10k_points");
    group.bench_function("read_csv", |b| {
        b.iter(|| read_text(black_box(&csv), Units::Mm).expect("valid"))
    });
    group.bench_function("analyse", |b| {
        b.iter(|| analyse(black_box(&curve), &AnalysisOptions::default()))
    });
    group.bench_function("ksa", |b| {
        b.iter(|| ksa(black_box(&curve), &params).expect("valid"))
    });
    group.bench_function("analyse_then_ksa", |b| {
        b.iter(|| {
            let a = analyse(black_box(&curve), &AnalysisOptions::default());
            (a, ksa(black_box(&curve), &params).expect("valid"))
        })
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
