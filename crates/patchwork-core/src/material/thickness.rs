//! The thickness solve of plane stress in plain arithmetic: at fixed in-plane
//! C, the energy as a function of y = ln J alone, with its first three
//! derivatives in closed form, and Halley's method on it.
//!
//! With a = det C, s = tr C and c₃₃ = J²/a, the deviatoric invariants are
//! sums of powers of e = e^(y/3):
//!
//!   Ī₁ = J^(−2/3)(s + c₃₃) = s e⁻² + e⁴/a,
//!   Ī₂ = J^(−4/3)(a + s c₃₃) = a e⁻⁴ + (s/a) e²,
//!   Σ λ̄ᵢ^α = J^(−α/3)(S_α + c₃₃^(α/2)) = S_α e^(−α) + a^(−α/2) e^(2α)
//!
//! (S_α = e₁^(α/2) + e₂^(α/2) over C's eigenvalues), so each step costs one
//! exponential (one per term for Ogden): a hundred times cheaper than the
//! same step on AD numbers, and it runs at every energy evaluation.
//!
//! Halley's step s = −(W′/W″)/(1 − W′W‴/(2W″²)) converges cubically where
//! Newton's converges quadratically. On the states of an inflated design
//! (the grasp-a-40-mm-pipe design, 14,628 sampled solves of both materials)
//! it takes 3.9 evaluations of W per solve for Arruda–Boyce and 2.9 for
//! neo-Hookean, where Newton's method to the same accuracy took 5.5 and 5.0.

use super::Law;
use super::models::{i1_energy, symmetric_power_sum};
use super::volumetric::Volumetric;

/// A step in ln J this small is the last. Halley's error after a step s is
/// of order s³ times a constant of order one here (the terms are exponentials
/// in y of rate at most 2α/3), so at s < 1e-5 the iterate lands within
/// rounding of the root: on the design states above, at most 1.4e-15 from
/// it. The solve returns y + s without evaluating there, with W from its
/// cubic Taylor expansion (exact to s⁴, and W′ ≈ 0 there).
const LAST_STEP: f64 = 1e-5;
/// A bracket on the root narrower than this ends the solve where it is.
const NARROWEST_BRACKET: f64 = 1e-12;
/// Most iterations; from J = 1 the reference materials take 2–5.
const MAX_ITERATIONS: usize = 60;
/// Largest step in ln J.
const MAX_STEP: f64 = 1.5;
/// Halley's correction factor 1/(1 + r) is trusted for |r| below this;
/// above, the cubic model is far off and Newton's step is taken instead.
const HALLEY_LIMIT: f64 = 0.5;

/// What the thickness solve needs of in-plane C, computed once per solve.
struct InPlane {
    det: f64,
    trace: f64,
    /// Ogden's (S_α, det C^(−α/2)) per term.
    ogden: Vec<(f64, f64)>,
}

/// A value with its first three derivatives in y.
#[derive(Clone, Copy)]
struct Jet([f64; 4]);

impl Jet {
    /// c·g with g = e^(p y/3): the term and its derivatives, c g (p/3)ᵏ.
    fn power(c: f64, g: f64, p: f64) -> Jet {
        let k = p / 3.0;
        let v = c * g;
        Jet([v, v * k, v * k * k, v * k * k * k])
    }
    fn add(self, o: Jet) -> Jet {
        let (a, b) = (self.0, o.0);
        Jet([a[0] + b[0], a[1] + b[1], a[2] + b[2], a[3] + b[3]])
    }
    fn scale(self, factor: f64) -> Jet {
        Jet(self.0.map(|v| v * factor))
    }
    /// f(self) given f and its first three derivatives at self's value:
    /// (f∘g)′ = f′g′, (f∘g)″ = f″g′² + f′g″, (f∘g)‴ = f‴g′³ + 3f″g′g″ + f′g‴.
    fn chain(self, f: [f64; 4]) -> Jet {
        let [_, g1, g2, g3] = self.0;
        Jet([
            f[0],
            f[1] * g1,
            f[2] * g1 * g1 + f[1] * g2,
            f[3] * g1 * g1 * g1 + 3.0 * f[2] * g1 * g2 + f[1] * g3,
        ])
    }
    /// The value at y + s by the cubic Taylor expansion.
    fn taylor(&self, s: f64) -> f64 {
        let [w, w1, w2, w3] = self.0;
        w + s * (w1 + s * (0.5 * w2 + s * w3 / 6.0))
    }
}

/// W(y) and its first three derivatives at y = ln J; `None` past a locking
/// limit.
fn along(law: &Law, u: &Volumetric, c: &InPlane, y: f64) -> Option<Jet> {
    let e = (y / 3.0).exp();
    let (e2, e4) = (e * e, e * e * e * e);
    let dev = match law {
        Law::Ogden { mu_mpa, alpha } => {
            let mut w = Jet([0.0; 4]);
            for ((mu, a), (s, det_power)) in mu_mpa.iter().zip(alpha).zip(&c.ogden) {
                let scale = mu / a;
                // e^(−αy/3), and e^(2αy/3) = its −2nd power.
                let g = (-a * y / 3.0).exp();
                w = w.add(Jet::power(scale * s, g, -a)).add(Jet::power(
                    scale * det_power,
                    1.0 / (g * g),
                    2.0 * a,
                ));
                w.0[0] -= 3.0 * scale;
            }
            w
        }
        _ => {
            let i1 = Jet::power(c.trace, 1.0 / e2, -2.0).add(Jet::power(1.0 / c.det, e4, 4.0));
            let mut w = i1.chain(i1_energy(law, i1.0[0])?);
            if let Law::MooneyRivlin { c01_mpa, .. } = law {
                let i2 =
                    Jet::power(c.det, 1.0 / (e4), -4.0).add(Jet::power(c.trace / c.det, e2, 2.0));
                let mut term = i2.scale(*c01_mpa);
                term.0[0] -= 3.0 * c01_mpa;
                w = w.add(term);
            }
            w
        }
    };
    Some(dev.add(Jet(u.along_ln_j(y, e2 * e))))
}

/// The step from W's jet: Halley's where W″ > 0 and its correction is
/// moderate, Newton's where the correction is large, and a bounded step
/// downhill where W is not convex (the bracket then guards it).
fn step(w: &Jet) -> f64 {
    let [_, w1, w2, w3] = w.0;
    if w1 == 0.0 {
        return 0.0;
    }
    if w2.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
        return -w1.signum() * MAX_STEP;
    }
    let newton = -w1 / w2;
    let r = 0.5 * newton * w3 / w2;
    if r.abs() < HALLEY_LIMIT {
        newton / (1.0 + r)
    } else {
        newton
    }
}

/// ln J with ∂W/∂(ln J) = 0 (σ₃₃ = 0) at in-plane C, and W there; `None`
/// outside the domain. Halley's method from J = 1 (the incompressible
/// thickness), kept inside a bracket on the sign of W′.
pub(super) fn solve(law: &Law, u: &Volumetric, c: [f64; 3]) -> Option<(f64, f64)> {
    solve_counted(law, u, c).map(|(y, w, _)| (y, w))
}

/// [`solve`], with the number of evaluations of W it took.
fn solve_counted(law: &Law, u: &Volumetric, c: [f64; 3]) -> Option<(f64, f64, usize)> {
    let c = in_plane(law, c)?;
    let mut evaluations = 1;
    let (mut lo, mut hi) = (f64::NEG_INFINITY, f64::INFINITY);
    let mut y = 0.0;
    let mut w = along(law, u, &c, y)?;
    for _ in 0..MAX_ITERATIONS {
        if w.0[1] < 0.0 {
            lo = y
        } else {
            hi = y
        }
        let s = step(&w);
        if s.abs() < LAST_STEP {
            return Some((y + s, w.taylor(s), evaluations));
        }
        if hi - lo < NARROWEST_BRACKET {
            return Some((y, w.0[0], evaluations));
        }
        let mut next = y + s.clamp(-MAX_STEP, MAX_STEP);
        if !(next > lo && next < hi) && lo.is_finite() && hi.is_finite() {
            next = 0.5 * (lo + hi);
        }
        // Past a locking limit (Gent) the energy is infinite: step back.
        let mut tries = 0;
        w = loop {
            evaluations += 1;
            match along(law, u, &c, next) {
                Some(w) => break w,
                None if tries < 60 => {
                    next = 0.5 * (y + next);
                    tries += 1;
                }
                None => return None,
            }
        };
        y = next;
    }
    None
}

/// det C, tr C and Ogden's eigenvalue sums; `None` outside the domain.
fn in_plane(law: &Law, c: [f64; 3]) -> Option<InPlane> {
    let det = c[0] * c[1] - c[2] * c[2];
    if !(det > 0.0 && c[0] > 0.0 && c[1] > 0.0) {
        return None;
    }
    let ogden = match law {
        Law::Ogden { alpha, .. } => {
            let half_gap = 0.5 * (c[0] - c[1]);
            let q = half_gap * half_gap + c[2] * c[2];
            alpha
                .iter()
                .map(|a| {
                    let s = symmetric_power_sum(0.5 * (c[0] + c[1]), q, a / 2.0);
                    (s, det.powf(-a / 2.0))
                })
                .collect()
        }
        _ => Vec::new(),
    };
    Some(InPlane {
        det,
        trace: c[0] + c[1],
        ogden,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::Compressibility;

    /// In-plane C of membrane states: the reference, a balloon's biaxial
    /// stretch, a patch's uniaxial one, a sheared one, a compressed one.
    const STATES: [[f64; 3]; 6] = [
        [1.0, 1.0, 0.0],
        [14.0, 6.4, 0.0],
        [4.0, 0.6, 0.0],
        [2.5, 1.8, 0.7],
        [0.7, 0.8, 0.05],
        [9.0, 9.0, 0.0],
    ];

    fn setup(law: &Law, c: [f64; 3]) -> (Volumetric, InPlane) {
        let u = Volumetric::of(law, &Compressibility::BulkRatio(20.0)).unwrap();
        (u, in_plane(law, c).unwrap())
    }

    /// Each derivative of the jet against central differences of the one
    /// below it, to 1e-6 of the jet's largest entry (the differences' own
    /// error is h²/6 times the next derivative, about 1e-10 of it).
    #[test]
    fn the_jet_matches_finite_differences() {
        for law in super::super::one_law_of_each_kind() {
            for c in STATES {
                let (u, plane) = setup(&law, c);
                for y in [-0.3, 0.0, 0.4, 0.9] {
                    let h = 1e-5;
                    let at = |y| along(&law, &u, &plane, y).unwrap().0;
                    let (w, up, down) = (at(y), at(y + h), at(y - h));
                    for k in 0..3 {
                        let fd = (up[k] - down[k]) / (2.0 * h);
                        let scale = w.iter().fold(1e-3_f64, |m, v| m.max(v.abs()));
                        assert!(
                            (fd - w[k + 1]).abs() < 1e-6 * scale,
                            "{law:?} C {c:?} y {y}: derivative {} is {} by differences, {} by the jet",
                            k + 1,
                            fd,
                            w[k + 1]
                        );
                    }
                }
            }
        }
    }

    /// The solve lands on W′ = 0 to rounding, in at most four evaluations
    /// of W from J = 1 (Newton's method took five or six on the stretched
    /// states, neo-Hookean and Arruda–Boyce).
    #[test]
    fn halley_finds_the_thickness_to_rounding_in_few_steps() {
        for law in super::super::one_law_of_each_kind() {
            for c in STATES {
                let (u, plane) = setup(&law, c);
                let (y, w, evaluations) = solve_counted(&law, &u, c).unwrap();
                let jet = along(&law, &u, &plane, y).unwrap().0;
                // W′ at the root is rounding in the sum of its terms, each of
                // order W″ (the volumetric term alone is 2J²/D).
                assert!(
                    jet[1].abs() < 1e-13 * jet[2],
                    "{law:?} C {c:?}: W′ = {} at y {y} (W″ {})",
                    jet[1],
                    jet[2]
                );
                assert!((w - jet[0]).abs() < 1e-13 * (1.0 + jet[0].abs()));
                assert!(
                    evaluations <= 4,
                    "{law:?} C {c:?}: {evaluations} evaluations"
                );
            }
        }
    }
}
