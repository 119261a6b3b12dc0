//! The balloon's sources as one variable. The membrane's energy per unit
//! of reference area is t·W, the modulus scaling W, so the wall and the
//! modulus act exactly as one; the pressure moves the centreline along
//! nearly the same field (its linearised move at every sample is within a
//! few degrees of theirs, cosine 0.95–0.999 on five draft designs). The
//! balloon's response to them together is strongly nonlinear — the
//! paper's balloon inflates on a soft branch, and a thinner, softer or
//! harder-pressed balloon moves much further than a thicker one moves
//! back — so their changes solved one by one at ±σ and added in
//! quadrature miss the larger moves of their joint tails.
//!
//! With cₖ the signed size of source k's linearised move along the
//! largest one's field (mm, RMS over the samples) and xₖ ~ N(0, 1) each,
//! the joined sources move the centreline by g(z), z = Σₖ cₖ xₖ ~
//! N(0, σ²), σ² = Σₖ cₖ². Its expected square and mean are found by
//! Gauss–Hermite quadrature on z: the design moved to z = ±√3 σ, every
//! joined source at xₖ = ±√3 cₖ/σ (the likeliest such draw), and
//! E|g|² = (|g₊|² + |g₋|²)/6, E[g] = (g₊ + g₋)/6 — exact where g is
//! quadratic, as the ±σ solves of one source are, but sampled where the
//! normal's weight of |g|² lies. Two solves for the balloon's three
//! sources, where solving the wall and the pressure both ways takes four.
//! Against sampling the balloon's sources (200 draws on the verification
//! model, five draft designs, the robust grasp of a 40 mm pipe and the
//! robust arc among them), the sampled RMS is 1.10–1.19 times this
//! estimate, against 1.12–1.40 times the sources' solved one by one
//! (docs/studies.md, "The spread's solves"). Each joined source is shown
//! with the share cₖ²/σ² of the whole.

use super::change::{Change, Nominal, Offsets, offsets_of};
use super::sources::Source;
use super::tolerances::Tolerances;
use crate::curve::{Curve, Point};
use crate::design::Design;
use crate::fe::{Simulation, simulate_with};

/// Gauss–Hermite nodes (in σ) and weights of the probabilists' rule with
/// three points, the centre's (weight 2/3, where g = 0) left out.
pub(super) const NODES: [(f64, f64); 1] = [(1.732_050_807_568_877_2, 1.0 / 6.0)];

/// The least |cosine| between a balloon source's linearised field and the
/// largest one's for it to join them.
pub(super) const JOIN_COSINE: f64 = 0.9;

/// The balloon's sources that act as one: each source's index and its
/// signed size cₖ along the shared field, and σ = √Σₖ cₖ².
pub(super) struct Joined {
    pub members: Vec<(usize, f64)>,
    pub sigma: f64,
}

impl Joined {
    /// The balloon's sources among `sources` whose linearised `fields`
    /// lie along the largest one's; none where no balloon source has a
    /// field.
    pub(super) fn of(sources: &[Source], fields: &[Option<Vec<Point>>]) -> Option<Joined> {
        let balloon: Vec<(usize, &Vec<Point>)> = (0..sources.len())
            .filter(|&k| !matches!(sources[k], Source::Patch { .. }))
            .filter_map(|k| Some((k, fields[k].as_ref()?)))
            .collect();
        let dot = |a: &[Point], b: &[Point]| a.iter().zip(b).map(|(x, y)| x.dot(y)).sum::<f64>();
        let (_, largest) = *balloon
            .iter()
            .max_by(|a, b| dot(a.1, a.1).total_cmp(&dot(b.1, b.1)))?;
        let norm = dot(largest, largest).sqrt();
        if norm == 0.0 {
            return None;
        }
        let members: Vec<(usize, f64)> = (balloon.iter())
            .filter_map(|&(k, field)| {
                let along = dot(field, largest) / norm;
                let cosine = along / dot(field, field).sqrt();
                let c = along / (field.len() as f64).sqrt();
                (cosine.abs() >= JOIN_COSINE).then_some((k, c))
            })
            .collect();
        let sigma = members.iter().map(|(_, c)| c * c).sum::<f64>().sqrt();
        (sigma > 0.0).then_some(Joined { members, sigma })
    }

    /// Whether source `k` is one of them.
    pub(super) fn has(&self, k: usize) -> bool {
        self.members.iter().any(|&(m, _)| m == k)
    }

    /// Each source's index and its share of the whole, cₖ²/σ².
    pub(super) fn shares(&self) -> impl Iterator<Item = (usize, f64)> + '_ {
        (self.members.iter()).map(|&(k, c)| (k, (c / self.sigma).powi(2)))
    }

    /// The quadrature's points (in σ): one solve each.
    pub(super) fn nodes() -> impl Iterator<Item = f64> {
        NODES.iter().flat_map(|&(n, _)| [n, -n])
    }

    /// The design moved to node `n` (every joined source at xₖ = n cₖ/σ)
    /// and solved on `nominal`, warm-started from the joined linearised
    /// states added up (`starts`, each at its tolerance): its offsets at
    /// `samples`.
    pub(super) fn node(
        &self,
        nominal: &Nominal,
        n: f64,
        (sources, tolerances): (&[Source], &Tolerances),
        starts: &[Option<Vec<Point>>],
        samples: &Curve,
    ) -> Result<Offsets, String> {
        let design = self.moved(nominal.design, n, (sources, tolerances));
        let start = self.start(nominal.simulation, n, starts);
        let solved = simulate_with(
            &design,
            &nominal.source_options(),
            Some(&start),
            nominal.patterns,
        )
        .map_err(|e| format!("the balloon's sources together at {n:+.2} σ: {e}"))?;
        offsets_of(&solved.centreline, &nominal.simulation.centreline, samples)
    }

    /// The joined sources' change together from their offsets at every
    /// one of [`Joined::nodes`], in order: the quadrature on z (see the
    /// module comment).
    pub(super) fn change(moved: &[Offsets]) -> Change {
        let weights: Vec<f64> = NODES.iter().flat_map(|&(_, w)| [w, w]).collect();
        quadrature(moved, &weights)
    }

    /// `design` with every joined source at xₖ = n cₖ/σ of its tolerance.
    fn moved(&self, design: &Design, n: f64, (sources, t): (&[Source], &Tolerances)) -> Design {
        self.members.iter().fold(design.clone(), |d, &(k, c)| {
            sources[k].moved(&d, n * c / self.sigma * sources[k].tolerance(t).0)
        })
    }

    /// The nominal state plus each joined source's linearised move, scaled
    /// to the node (the nominal where a source has no linearised state).
    fn start(&self, nominal: &Simulation, n: f64, starts: &[Option<Vec<Point>>]) -> Simulation {
        let x0 = &nominal.positions;
        let mut positions = x0.clone();
        for &(k, c) in &self.members {
            let Some(linearised) = starts[k].as_ref().filter(|l| l.len() == x0.len()) else {
                continue;
            };
            let scale = n * c / self.sigma;
            for ((x, l), a) in positions.iter_mut().zip(linearised).zip(x0) {
                *x += (l - a) * scale;
            }
        }
        Simulation {
            positions,
            ..nominal.clone()
        }
    }
}

/// E|g|² and E[g] at every sample and at the tip from the moves at the
/// quadrature's nodes and their weights.
fn quadrature(moved: &[Offsets], weights: &[f64]) -> Change {
    let samples = moved.first().map_or(0, |m| m.residuals.len());
    let each_sq = (0..samples)
        .map(|i| {
            let sq = moved.iter().map(|m| m.residuals[i].norm_squared());
            sq.zip(weights).map(|(s, w)| s * w).sum()
        })
        .collect();
    let shift = (0..samples)
        .map(|i| {
            (moved.iter().zip(weights))
                .map(|(m, w)| m.residuals[i] * *w)
                .sum()
        })
        .collect();
    let tip_sq: f64 = (moved.iter().zip(weights))
        .map(|(m, w)| m.tip.norm_squared() * w)
        .sum();
    Change {
        each_sq,
        tip_mm: tip_sq.sqrt(),
        shift,
        tip_shift: (moved.iter().zip(weights)).map(|(m, w)| m.tip * *w).sum(),
    }
}

/// `change`'s part `share`: the share of its scatter and of its mean,
/// E|dₖ|² = s (E|d|² − |b|²) + s²|b|², bₖ = s b — so the parts, added as
/// independent sources are (`linear::Together`), give back the whole.
pub(super) fn apportioned(change: &Change, share: f64) -> Change {
    let part = |sq: f64, b: &Point| share * (sq - b.norm_squared()) + (share * b).norm_squared();
    change.reread(part, share)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The rule integrates x² and x⁴ of a standard normal: 1 and 3 (the
    /// centre's weight, 2/3, at x = 0 adds nothing to them).
    #[test]
    fn the_nodes_integrate_even_powers_of_a_normal() {
        for (power, expected) in [(2, 1.0), (4, 3.0)] {
            let sum: f64 = NODES
                .iter()
                .map(|&(n, w)| 2.0 * w * f64::powi(n, power))
                .sum();
            assert!(
                (sum - expected).abs() < 1e-12 * expected,
                "x^{power}: {sum}"
            );
        }
        let total: f64 = NODES.iter().map(|&(_, w)| 2.0 * w).sum();
        assert!((total + 2.0 / 3.0 - 1.0).abs() < 1e-12, "{total}");
    }

    /// Parts of a change with a mean, added as independent sources (their
    /// scatters summed, their means as vectors), give back the whole.
    #[test]
    fn the_parts_add_up_to_the_whole() {
        let whole = Change {
            each_sq: vec![9.0, 4.0],
            tip_mm: 5.0,
            shift: vec![Point::new(1.0, 2.0, 0.0), Point::new(0.0, 0.0, -1.5)],
            tip_shift: Point::new(3.0, 0.0, 0.0),
        };
        let parts: Vec<Change> = [0.6, 0.3, 0.1].map(|s| apportioned(&whole, s)).into();
        for i in 0..2 {
            let scatter: f64 = (parts.iter())
                .map(|p| p.each_sq[i] - p.shift[i].norm_squared())
                .sum();
            let mean: Point = parts.iter().map(|p| p.shift[i]).sum();
            let sum = scatter + mean.norm_squared();
            assert!((sum - whole.each_sq[i]).abs() < 1e-12, "{sum}");
        }
        let tip: f64 = parts
            .iter()
            .map(|p| p.tip_mm.powi(2) - p.tip_shift.norm_squared())
            .sum();
        let tip_mean: Point = parts.iter().map(|p| p.tip_shift).sum();
        assert!((tip + tip_mean.norm_squared() - 25.0).abs() < 1e-12);
    }
}
