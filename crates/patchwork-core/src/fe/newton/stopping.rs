//! When a solve stops: past its iteration cap it may go on while the
//! residual still falls (quadratically, or crawling), up to a hard limit.

/// Extra iterations allowed past `max_iterations` while Newton is in its
/// quadratic phase, where convergence is a few iterations away. Seen on a 2 m
/// balloon with many patches: 55 iterations of slow progress at a relative
/// residual near 1e-3, then 8.7e-6, 2.6e-6, 1.3e-7, 1.03e-9 at the cap of 60
/// against a tolerance of 1e-9 — one iteration short.
const QUADRATIC_GRACE: usize = 5;

/// A solve past `max_iterations` may run to `EXTENSION` times it while it
/// still makes progress ([`crawling`]).
const EXTENSION: usize = 3;

/// Iterations of the windows that [`crawling`] compares.
const PROGRESS_WINDOW: usize = 20;

/// The last iteration any solve with this cap may reach.
pub fn hard_limit(max_iterations: usize) -> usize {
    max_iterations * EXTENSION + QUADRATIC_GRACE
}

/// Past `max_iterations`, whether Newton should go on: in its quadratic phase,
/// or still crawling towards the solution. Either way the solve ends at
/// [`hard_limit`], or at its time limit.
pub fn still_converging(residuals: &[f64]) -> bool {
    converging_quadratically(residuals) || crawling(residuals)
}

/// The last two iterations each cut the residual at least tenfold.
fn converging_quadratically(residuals: &[f64]) -> bool {
    let [.., a, b, c] = residuals else {
        return false;
    };
    *b <= 0.1 * a && *c <= 0.1 * b
}

/// The smallest residual of the last [`PROGRESS_WINDOW`] iterations is at
/// most a third of the smallest of the window before. A long balloon winding
/// into a coil (soft winding modes) spends dozens of iterations with the
/// residual oscillating around 1e-3…1e-4 while the energy falls, before the
/// quadratic phase (2 m helix, 3 mm elements: best 1.5e-4 → 2.2e-5 over
/// iterations 20–60, converged at 68; cut off at 60, the continuation
/// restarted from the straight tube at half the patch stiffness: 286
/// iterations in all against 128).
fn crawling(residuals: &[f64]) -> bool {
    let n = residuals.len();
    if n < 2 * PROGRESS_WINDOW {
        return false;
    }
    let smallest = |w: &[f64]| w.iter().copied().fold(f64::INFINITY, f64::min);
    let recent = smallest(&residuals[n - PROGRESS_WINDOW..]);
    let before = smallest(&residuals[n - 2 * PROGRESS_WINDOW..n - PROGRESS_WINDOW]);
    recent <= before / 3.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grace_only_while_the_residual_falls_fast() {
        assert!(converging_quadratically(&[1e-3, 8.7e-6, 1.3e-7, 1.03e-9]));
        assert!(!converging_quadratically(&[8.7e-6, 2.6e-6, 1.3e-7]));
        assert!(!converging_quadratically(&[1e-3, 5e-4, 1e-3]));
        assert!(!converging_quadratically(&[1e-9]));
    }

    #[test]
    fn extension_only_while_the_residual_keeps_falling() {
        // The 2 m helix's failed start: oscillating between 1e-3 and a best of
        // 3e-4, then of 2.5e-4: no real progress.
        let stuck: Vec<f64> = (0..40)
            .map(|i| match (i % 2, i < 20) {
                (0, _) => 1e-3,
                (_, true) => 3e-4,
                (_, false) => 2.5e-4,
            })
            .collect();
        assert!(!crawling(&stuck));
        // Best of the last twenty a fifth of the twenty before: crawling.
        let falling: Vec<f64> = (0..40).map(|i| 1e-3 * 0.92_f64.powi(i)).collect();
        assert!(crawling(&falling));
        assert!(still_converging(&falling));
        // Too short a history to judge.
        assert!(!crawling(&falling[..39]));
    }

    #[test]
    fn the_hard_limit_is_three_caps_and_the_grace() {
        assert_eq!(hard_limit(60), 185);
    }
}
