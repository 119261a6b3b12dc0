//! The thickness solve of plane stress in plain arithmetic: at fixed in-plane
//! C, the energy as a function of y = ln J alone, with its first two
//! derivatives in closed form, and Newton's method on it.
//!
//! With a = det C, s = tr C and c₃₃ = J²/a, the deviatoric invariants are
//! sums of powers of e = e^(y/3):
//!
//!   Ī₁ = J^(−2/3)(s + c₃₃) = s e⁻² + e⁴/a,
//!   Ī₂ = J^(−4/3)(a + s c₃₃) = a e⁻⁴ + (s/a) e²,
//!   Σ λ̄ᵢ^α = J^(−α/3)(S_α + c₃₃^(α/2)) = S_α e^(−α) + a^(−α/2) e^(2α)
//!
//! (S_α = e₁^(α/2) + e₂^(α/2) over C's eigenvalues), so each Newton step costs
//! one exponential (one per term for Ogden): a hundred times cheaper than
//! the same step on AD numbers, and it runs at every energy evaluation.

use super::Law;
use super::models::{i1_energy, symmetric_power_sum};
use super::volumetric::Volumetric;

/// Newton's step in ln J below which the iterate is converged. The membrane's
/// stress inherits the thickness's error times a bulk-modulus-sized factor:
/// at 1e-7 the FE residual stalled near 2e-9 (its tolerance is 1e-9), so the
/// solve goes to rounding. Where rounding stops the steps from shrinking
/// (a small step not half the previous one), the iterate is taken as it is.
const FINAL_STEP: f64 = 1e-12;
/// Steps below this are in the rounding-limited regime.
const SMALL_STEP: f64 = 1e-7;
/// Most Newton iterations; from J = 1 the reference materials take 3–6.
const MAX_ITERATIONS: usize = 60;
/// Largest step in ln J.
const MAX_STEP: f64 = 1.5;

/// What the thickness solve needs of in-plane C, computed once per solve.
struct InPlane {
    det: f64,
    trace: f64,
    /// Ogden's (S_α, det C^(−α/2)) per term.
    ogden: Vec<(f64, f64)>,
}

/// A value with its first two derivatives in y.
#[derive(Clone, Copy)]
struct Jet(f64, f64, f64);

impl Jet {
    /// c·e^(p y/3)·… given g = e^(p y/3): the term and its derivatives.
    fn power(c: f64, g: f64, p: f64) -> Jet {
        let k = p / 3.0;
        Jet(c * g, c * g * k, c * g * k * k)
    }
    fn add(self, o: Jet) -> Jet {
        Jet(self.0 + o.0, self.1 + o.1, self.2 + o.2)
    }
    /// f(self) given f, f′, f″ at self's value.
    fn chain(self, f: (f64, f64, f64)) -> Jet {
        Jet(f.0, f.1 * self.1, f.2 * self.1 * self.1 + f.1 * self.2)
    }
}

/// W(y), W′(y), W″(y) at y = ln J; `None` past a locking limit.
fn along(law: &Law, u: &Volumetric, c: &InPlane, y: f64) -> Option<Jet> {
    let e = (y / 3.0).exp();
    let (e2, e4) = (e * e, e * e * e * e);
    let dev = match law {
        Law::Ogden { mu_mpa, alpha } => {
            let mut w = Jet(0.0, 0.0, 0.0);
            for ((mu, a), (s, det_power)) in mu_mpa.iter().zip(alpha).zip(&c.ogden) {
                let scale = mu / a;
                // e^(−αy/3), and e^(2αy/3) = its −2nd power.
                let g = (-a * y / 3.0).exp();
                w = w.add(Jet::power(scale * s, g, -a)).add(Jet::power(
                    scale * det_power,
                    1.0 / (g * g),
                    2.0 * a,
                ));
                w.0 -= 3.0 * scale;
            }
            w
        }
        _ => {
            let i1 = Jet::power(c.trace, 1.0 / e2, -2.0).add(Jet::power(1.0 / c.det, e4, 4.0));
            let mut w = i1.chain(i1_energy(law, i1.0)?);
            if let Law::MooneyRivlin { c01_mpa, .. } = law {
                let i2 =
                    Jet::power(c.det, 1.0 / (e4), -4.0).add(Jet::power(c.trace / c.det, e2, 2.0));
                w = w.add(Jet((i2.0 - 3.0) * c01_mpa, i2.1 * c01_mpa, i2.2 * c01_mpa));
            }
            w
        }
    };
    let (vol, dvol, d2vol) = u.along_ln_j(e2 * e);
    Some(dev.add(Jet(vol, dvol, d2vol)))
}

/// ln J with ∂W/∂(ln J) = 0 (σ₃₃ = 0) at in-plane C, and W there; `None`
/// outside the domain. Newton from J = 1 (the incompressible thickness),
/// kept inside a bracket on the sign of W′.
pub(super) fn solve(law: &Law, u: &Volumetric, c: [f64; 3]) -> Option<(f64, f64)> {
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
    let c = InPlane {
        det,
        trace: c[0] + c[1],
        ogden,
    };
    let (mut lo, mut hi) = (f64::NEG_INFINITY, f64::INFINITY);
    let mut y = 0.0;
    let mut w = along(law, u, &c, y)?;
    let mut previous = f64::INFINITY;
    for _ in 0..MAX_ITERATIONS {
        if w.1 < 0.0 {
            lo = y
        } else {
            hi = y
        }
        // At an exact root the step is zero and the test below returns.
        let step = if w.1 == 0.0 {
            0.0
        } else if w.2 > 0.0 {
            -w.1 / w.2
        } else {
            -w.1.signum() * MAX_STEP
        };
        // A step at rounding level: y is the root (stepping could only land
        // on the bracket's end and set off a bisection).
        if step.abs() < FINAL_STEP * (1.0 + y.abs()) {
            return Some((y, w.0));
        }
        let mut next = y + step.clamp(-MAX_STEP, MAX_STEP);
        if !(next > lo && next < hi) && lo.is_finite() && hi.is_finite() {
            next = 0.5 * (lo + hi);
        }
        let size = (next - y).abs();
        let converged = size < FINAL_STEP * (1.0 + y.abs())
            || (size < SMALL_STEP && size > 0.5 * previous)
            || hi - lo < FINAL_STEP;
        previous = size;
        // Past a locking limit (Gent) the energy is infinite: step back.
        let mut tries = 0;
        w = loop {
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
        if converged {
            return Some((y, w.0));
        }
    }
    None
}
