//! Backtracking line search (Armijo).

use super::potential::Potential;

/// Whether Π = `value` at the fraction `t` of a step satisfies Armijo's
/// condition Π ≤ Π₀ + c·t·slope from Π₀ = `energy`, with c = 1e-4, less an
/// allowance. Π is a sum of ~10⁴ element energies minus a large P·V, so its
/// rounding noise is near 1e-12·|Π|; the allowance of 1e-11·|Π| keeps the
/// last iterations, whose true energy change is below that noise, from
/// being rejected. Far from equilibrium real decreases dwarf it.
pub fn sufficient_decrease(energy: f64, slope: f64, t: f64, value: f64) -> bool {
    let allowance = 1e-11 * energy.abs();
    value.is_finite() && value <= energy + 1e-4 * t * slope + allowance
}

/// The first point u + t·step, t = `first`, `first`/2, `first`/4, … (down to
/// 1e-10), whose energy passes [`sufficient_decrease`]; none if no t does.
pub fn line_search(
    potential: &impl Potential,
    u: &[f64],
    step: &[f64],
    (energy, slope): (f64, f64),
    first: f64,
) -> Option<Vec<f64>> {
    let mut t = first;
    while t > 1e-10 {
        let trial = potential.advanced(u, step, t);
        if sufficient_decrease(energy, slope, t, potential.energy(&trial)) {
            return Some(trial);
        }
        t *= 0.5;
    }
    None
}
