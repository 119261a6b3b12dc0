//! Backtracking line search (Armijo).

use super::potential::Potential;

/// The first point u + t·step, t = 1, ½, ¼, … (down to 1e-10), whose energy
/// satisfies Armijo's condition Π ≤ Π₀ + c·t·slope with c = 1e-4, less an
/// allowance; none if no t does. Π is a sum of ~10⁴ element energies minus a
/// large P·V, so its rounding noise is near 1e-12·|Π|; the allowance of
/// 1e-11·|Π| keeps the last iterations, whose true energy change is below
/// that noise, from being rejected. Far from equilibrium real decreases
/// dwarf it.
pub fn line_search(
    potential: &impl Potential,
    u: &[f64],
    step: &[f64],
    energy: f64,
    slope: f64,
) -> Option<Vec<f64>> {
    let mut t = 1.0;
    let allowance = 1e-11 * energy.abs();
    while t > 1e-10 {
        let trial: Vec<f64> = u.iter().zip(step).map(|(a, s)| a + t * s).collect();
        let value = potential.energy(&trial);
        if value.is_finite() && value <= energy + 1e-4 * t * slope + allowance {
            return Some(trial);
        }
        t *= 0.5;
    }
    None
}
