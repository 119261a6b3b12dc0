//! The designs the kinematic-start and rod-model studies share: ten
//! curves' KSA seeds on the reference balloon and CMA-ES-sized
//! perturbations of them (σ 0.2 in the unit cube); and their median.

use patchwork_core::cmaes::SeededRng;
use patchwork_core::curve::{Curve, Preset, ReferenceCurve};
use patchwork_core::design::Design;
use patchwork_core::inverse::{DesignSpace, Freedom, VariableBounds};
use patchwork_core::ksa::{KsaParams, ksa};
use patchwork_core::material::Compressibility;

/// The uninflated length a curve is seeded on: its length over the
/// reference balloon's inflated axial stretch, about 3.
const STRETCH: f64 = 3.0;

pub fn curves() -> Vec<(String, Curve)> {
    let mut curves: Vec<(String, Curve)> = [
        ReferenceCurve::Hilbert,
        ReferenceCurve::Pancake,
        ReferenceCurve::Spring,
    ]
    .into_iter()
    .map(|c| (c.name().to_string(), c.curve()))
    .collect();
    for name in [
        "helix", "grasp", "hook", "s_curve", "arc", "spiral", "trefoil",
    ] {
        let preset = Preset::from_name(name, serde_json::json!({})).expect("a preset");
        curves.push((name.to_string(), preset.curve(None).expect("a curve")));
    }
    curves
}

/// The seed design and `count` perturbations of it.
pub fn designs(
    curve: &Curve,
    count: usize,
    rng: &mut SeededRng,
    incompressible: bool,
) -> Vec<Design> {
    let l0 = curve.length() / STRETCH;
    let params = KsaParams {
        l0_mm: l0,
        ..KsaParams::default()
    };
    let seed = ksa(curve, &params).expect("KSA");
    let mut design = Design::reference(seed.patches);
    design.balloon.length_mm = l0;
    if incompressible {
        design = design.with_compressibility(Compressibility::Incompressible);
    }
    let mut near = perturbed(&design, count, 0.2, rng);
    near.insert(0, design);
    near
}

/// `count` perturbations of `base`'s patches at `sigma` in the unit cube
/// of the default bounds around them.
pub fn perturbed(base: &Design, count: usize, sigma: f64, rng: &mut SeededRng) -> Vec<Design> {
    let space = DesignSpace::new(
        base.patches.clone(),
        Freedom::default(),
        &VariableBounds::default(),
        base.balloon.length_mm,
    )
    .expect("valid bounds");
    let centre = space.seed_point();
    (0..count)
        .map(|_| {
            let u: Vec<f64> = (centre.iter())
                .map(|c| (c + sigma * rng.normal()).clamp(0.0, 1.0))
                .collect();
            Design {
                patches: space.patches(&u),
                ..base.clone()
            }
        })
        .collect()
}

/// The median (the upper of the two middle values; NaN when empty).
pub fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    match v.len() {
        0 => f64::NAN,
        n => v[n / 2],
    }
}
