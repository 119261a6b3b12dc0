//! Membrane theory of a long closed-end tube under internal pressure P: the
//! uniform state far from the ends, used as Newton's starting point.
//!
//! With hoop stretch λ₁, axial stretch λ₂, thickness stretch λ₃ (1/(λ₁λ₂)
//! when incompressible, from σ₃₃ = 0 otherwise: the material condenses it) and
//! W per reference volume, the membrane tensions per current length are
//! Tᵢ = t₀ (∂W/∂λᵢ)/λⱼ, and equilibrium of a ring and of the end cap give
//!
//!   hoop:  P R₀ / t₀ = (∂W/∂λ₁) / (λ₁ λ₂)
//!   axial: λ₁ ∂W/∂λ₁ = 2 λ₂ ∂W/∂λ₂
//!
//! For rubber the pressure rises, peaks (a bulge forms), falls and, for
//! stiffening models, rises again. We return the state on the *last rising
//! branch*: the stable one that a pressure-controlled inflation ends on.

use std::sync::Mutex;

use crate::design::Design;
use crate::material::Material;

/// Uniform stretches of the bare tube.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TubeState {
    /// Hoop stretch λ₁ (inflated radius / R₀).
    pub hoop: f64,
    /// Axial stretch λ₂.
    pub axial: f64,
}

/// Largest hoop stretch searched: beyond any latex balloon's burst. A
/// simulated state with a ring inflated further is refused as burst.
pub const MAX_HOOP: f64 = 12.0;
/// Scan step in λ₁. Rising and falling branches of p(λ₁) are ~0.5 wide for
/// rubber; 0.02 finds every crossing of them at a tenth of the cost of 0.005
/// (this runs on every forward solve).
const SCAN_STEP: f64 = 0.02;
/// Bisections stop at this relative bracket width (well below any use).
const ROOT_TOLERANCE: f64 = 1e-12;

/// Axial stretch in equilibrium with hoop stretch `hoop` (root of the axial
/// equation by bisection), or `None` if none lies in (0.2, 50).
pub fn axial_for_hoop(material: &Material, hoop: f64) -> Option<f64> {
    let g = |axial: f64| {
        let (w, w1, w2) = material.principal(hoop, axial);
        w.is_finite().then_some(hoop * w1 - 2.0 * axial * w2)
    };
    // Bracket by scanning outward from λ₂ = 1, which is always admissible: a
    // fixed wide bracket would reach past a locking limit (Gent) where the
    // energy is infinite.
    let (mut lo, mut hi, mut g_lo) = bracket(&g, 1.05).or_else(|| bracket(&g, 1.0 / 1.05))?;
    if lo > hi {
        std::mem::swap(&mut lo, &mut hi);
        g_lo = g(lo)?;
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        let g_mid = g(mid)?;
        if g_mid.signum() == g_lo.signum() {
            lo = mid;
            g_lo = g_mid;
        } else {
            hi = mid;
        }
        if hi - lo < ROOT_TOLERANCE * hi {
            break;
        }
    }
    Some(0.5 * (lo + hi))
}

/// Scans λ₂ = 1, f, f², … until `g` changes sign; (last, next, g(last)).
fn bracket(g: &impl Fn(f64) -> Option<f64>, factor: f64) -> Option<(f64, f64, f64)> {
    let mut a = 1.0;
    let mut g_a = g(a)?;
    while (0.05..50.0).contains(&a) {
        let b = a * factor;
        let g_b = g(b)?;
        if g_b.signum() != g_a.signum() {
            return Some((a, b, g_a));
        }
        (a, g_a) = (b, g_b);
    }
    None
}

/// P R₀ / t₀ (MPa) at hoop stretch `hoop`, with the axial stretch in equilibrium.
pub fn pressure_ratio(material: &Material, hoop: f64) -> Option<(f64, f64)> {
    let axial = axial_for_hoop(material, hoop)?;
    let (w, w1, _) = material.principal(hoop, axial);
    w.is_finite().then(|| (w1 / (hoop * axial), axial))
}

/// Tube states already found, per material and P R₀/t₀: every forward solve
/// of a run asks for the same one, and the scan below costs about 35 ms on
/// the compressible reference balloon (its thickness is solved at each of
/// some 550 hoop stretches) — as much as a warm solve on the search model.
static KNOWN: Mutex<Vec<(Material, u64, Option<TubeState>)>> = Mutex::new(Vec::new());

/// How many (material, load) states [`KNOWN`] keeps.
const KNOWN_STATES: usize = 16;

/// The inflated radius (mm, mid-wall) of `design`'s balloon without
/// patches: the widest its tube inflates, patches only narrowing it; none if
/// no rising branch reaches the design's pressure.
pub fn bare_radius(design: &Design) -> Option<f64> {
    let b = &design.balloon;
    let state = inflate_tube(&b.material, design.pressure_mpa(), b.radius_mm, b.wall_mm)?;
    Some(state.hoop * b.radius_mm)
}

/// The stable uniform state at pressure `pressure_mpa` of a tube with radius
/// `r0` and wall `t0`, or `None` if no rising branch reaches that pressure.
pub fn inflate_tube(material: &Material, pressure_mpa: f64, r0: f64, t0: f64) -> Option<TubeState> {
    let target = pressure_mpa * r0 / t0;
    let key = target.to_bits();
    let known = |cache: &Vec<(Material, u64, Option<TubeState>)>| {
        cache
            .iter()
            .find(|(m, k, _)| *k == key && m == material)
            .map(|(_, _, state)| *state)
    };
    // A poisoned lock only means another thread panicked mid-insert; the
    // states in it are still whole.
    let lock = || KNOWN.lock().unwrap_or_else(|e| e.into_inner());
    if let Some(state) = known(&lock()) {
        return state;
    }
    let state = scan(material, target);
    let mut cache = lock();
    if known(&cache).is_none() {
        if cache.len() == KNOWN_STATES {
            cache.remove(0);
        }
        cache.push((material.clone(), key, state));
    }
    state
}

/// The state at P R₀/t₀ = `target` (MPa): the last upward crossing of the
/// scanned p(λ₁), refined by bisection.
fn scan(material: &Material, target: f64) -> Option<TubeState> {
    if target == 0.0 {
        return Some(TubeState {
            hoop: 1.0,
            axial: 1.0,
        });
    }
    // Scan λ₁ upward, remembering the last upward crossing of the target.
    let mut crossing = None;
    let mut previous = (1.0, 0.0);
    let mut hoop = 1.0;
    while hoop < MAX_HOOP {
        hoop += SCAN_STEP;
        let Some((p, _)) = pressure_ratio(material, hoop) else {
            break;
        };
        if previous.1 < target && p >= target {
            crossing = Some((previous.0, hoop));
        }
        previous = (hoop, p);
    }
    let (mut lo, mut hi) = crossing?;
    while hi - lo > ROOT_TOLERANCE * hi {
        let mid = 0.5 * (lo + hi);
        let (p, _) = pressure_ratio(material, mid)?;
        if p < target { lo = mid } else { hi = mid }
    }
    let hoop = 0.5 * (lo + hi);
    let axial = axial_for_hoop(material, hoop)?;
    Some(TubeState { hoop, axial })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn neo_hookean_axial_equation_matches_design_values() {
        let m = Material::incompressible(crate::material::Law::NeoHookean { mu_mpa: 1.0 });
        for (l1, l2) in [(1.5, 1.138601), (2.0, 1.435500), (3.0, 2.124220)] {
            assert!((axial_for_hoop(&m, l1).unwrap() - l2).abs() < 1e-5);
        }
    }
}
