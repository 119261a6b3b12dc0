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
/// of a run asks for the same one, and the scan below costs about 3 ms on
/// the compressible reference balloon (its thickness is solved at each of
/// some 550 hoop stretches, and at each step of the bisection).
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
///
/// The scan only has to find that crossing, so it takes each hoop
/// stretch's axial stretch by a few secant steps from the last one's
/// ([`axial_near`]) instead of bracketing it afresh from λ₂ = 1 and
/// bisecting to the root (about 60 evaluations of W each). The crossing it
/// finds is then confirmed with the roots as [`pressure_ratio`] finds them,
/// and the bisection on λ₁ uses those, so the state is the one a scan on
/// them gives, to the last bit. Where the secants do not settle at a hoop
/// stretch, its axial stretch is bracketed as [`pressure_ratio`] does;
/// where the crossing is not confirmed, the scan runs again on
/// [`pressure_ratio`] itself.
/// On the compressible reference balloon this takes a state from 21.1 to
/// 2.9 ms (`cargo bench -p patchwork-core --bench material -- "tube
/// state"`, the two builds back to back).
fn scan(material: &Material, target: f64) -> Option<TubeState> {
    if target == 0.0 {
        return Some(TubeState {
            hoop: 1.0,
            axial: 1.0,
        });
    }
    let exact = |hoop: f64| pressure_ratio(material, hoop).map(|(p, _)| p);
    let confirmed = |(lo, hi): (f64, f64)| {
        // The scan's first point below is λ₁ = 1 at p = 0.
        let below = if lo == 1.0 { Some(0.0) } else { exact(lo) };
        matches!((below, exact(hi)), (Some(a), Some(b)) if a < target && b >= target)
    };
    let bracket = quick_crossing(material, target)
        .filter(|&bracket| confirmed(bracket))
        .or_else(|| last_crossing(target, exact))?;
    refined(material, target, bracket)
}

/// [`last_crossing`] of p(λ₁) with each axial stretch from the last one's
/// by [`axial_near`] (bracketed afresh where the secants do not settle).
fn quick_crossing(material: &Material, target: f64) -> Option<(f64, f64)> {
    let mut axial = 1.0;
    last_crossing(target, |hoop| {
        axial = axial_near(material, hoop, axial).or_else(|| axial_for_hoop(material, hoop))?;
        let (w, w1, _) = material.principal(hoop, axial);
        w.is_finite().then(|| w1 / (hoop * axial))
    })
}

/// The state where p(λ₁) = `target` within `(lo, hi)`, by bisection on
/// [`pressure_ratio`].
fn refined(material: &Material, target: f64, (mut lo, mut hi): (f64, f64)) -> Option<TubeState> {
    while hi - lo > ROOT_TOLERANCE * hi {
        let mid = 0.5 * (lo + hi);
        let (p, _) = pressure_ratio(material, mid)?;
        if p < target { lo = mid } else { hi = mid }
    }
    let hoop = 0.5 * (lo + hi);
    let axial = axial_for_hoop(material, hoop)?;
    Some(TubeState { hoop, axial })
}

/// The last λ₁-bracket (λ₁ up to [`MAX_HOOP`] in [`SCAN_STEP`]s from 1,
/// where p = 0) over which `pressure` (P R₀/t₀ at λ₁) rises through
/// `target`; the scan stops where `pressure` has no value.
fn last_crossing(target: f64, mut pressure: impl FnMut(f64) -> Option<f64>) -> Option<(f64, f64)> {
    let mut crossing = None;
    let mut previous = (1.0, 0.0);
    let mut hoop = 1.0;
    while hoop < MAX_HOOP {
        hoop += SCAN_STEP;
        let Some(p) = pressure(hoop) else {
            break;
        };
        if previous.1 < target && p >= target {
            crossing = Some((previous.0, hoop));
        }
        previous = (hoop, p);
    }
    crossing
}

/// The axial stretch in equilibrium with `hoop` by secant steps from
/// `guess` (the neighbouring hoop stretch's), to a relative 1e-10: enough
/// to tell on which side of a target p lies. None where the steps leave
/// the material's domain, jump by more than half the stretch or do not
/// settle within [`SECANT_STEPS`].
fn axial_near(material: &Material, hoop: f64, guess: f64) -> Option<f64> {
    let g = |axial: f64| {
        let (w, w1, w2) = material.principal(hoop, axial);
        w.is_finite().then_some(hoop * w1 - 2.0 * axial * w2)
    };
    let (mut a, mut b) = (guess, guess * 1.001);
    let (mut g_a, mut g_b) = (g(a)?, g(b)?);
    for _ in 0..SECANT_STEPS {
        if g_b == g_a {
            return None;
        }
        let next = b - g_b * (b - a) / (g_b - g_a);
        if next.is_nan() || next <= 0.0 || (next - b).abs() > 0.5 * b {
            return None;
        }
        if (next - b).abs() <= 1e-10 * next {
            return Some(next);
        }
        (a, g_a) = (b, g_b);
        (b, g_b) = (next, g(next)?);
    }
    None
}

/// Secant steps [`axial_near`] takes before it gives up.
const SECANT_STEPS: usize = 12;

#[cfg(test)]
mod tests {
    use super::*;

    use crate::material::Compressibility;

    /// Materials of every law, compressible and not, with loads (P R₀/t₀,
    /// MPa) on their rising branches and beyond their limit points.
    fn cases() -> Vec<(Material, Vec<f64>)> {
        let laws = crate::material::one_law_of_each_kind();
        let loads = vec![0.05, 0.2, 0.3, 0.35, 0.6, 1.5];
        let mut cases = vec![(Material::reference_balloon(), loads.clone())];
        for law in laws {
            cases.push((Material::incompressible(law.clone()), loads.clone()));
            let bulk = Compressibility::BulkRatio(20.0);
            cases.push((Material::compressible(law, bulk), loads.clone()));
        }
        cases
    }

    /// The scan on secant roots finds the crossing the scan on
    /// [`pressure_ratio`]'s roots finds (so it is confirmed, not replaced),
    /// and the state is that scan's to the last bit, or none where it has
    /// none.
    #[test]
    fn the_quick_scan_finds_the_exact_scans_state() {
        let mut found = 0;
        for (material, loads) in cases() {
            for target in loads {
                let exact = |hoop: f64| pressure_ratio(&material, hoop).map(|(p, _)| p);
                let bracket = last_crossing(target, exact);
                let case = format!("{material:?} at {target}");
                assert_eq!(quick_crossing(&material, target), bracket, "{case}");
                let expected = bracket.and_then(|b| refined(&material, target, b));
                assert_eq!(scan(&material, target), expected, "{case}");
                found += usize::from(expected.is_some());
            }
        }
        // The rest have no rising branch that reaches their load.
        assert_eq!(found, 46, "states found");
    }

    /// Each secant root lies within 1e-9 of the bracketed one along a scan
    /// of the reference balloon (the secants do the scan's work rather than
    /// fall back on every point).
    #[test]
    fn secant_roots_follow_the_bracketed_ones() {
        let material = Material::reference_balloon();
        let mut axial = 1.0;
        for k in 1..300 {
            let hoop = 1.0 + 0.02 * k as f64;
            let near = axial_near(&material, hoop, axial).expect("the secant settles");
            let exact = axial_for_hoop(&material, hoop).unwrap();
            assert!(
                (near - exact).abs() < 1e-9 * exact,
                "λ₁ {hoop}: {near} vs {exact}"
            );
            axial = near;
        }
    }

    #[test]
    fn neo_hookean_axial_equation_matches_design_values() {
        let m = Material::incompressible(crate::material::Law::NeoHookean { mu_mpa: 1.0 });
        for (l1, l2) in [(1.5, 1.138601), (2.0, 1.435500), (3.0, 2.124220)] {
            assert!((axial_for_hoop(&m, l1).unwrap() - l2).abs() < 1e-5);
        }
    }
}
