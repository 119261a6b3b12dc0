//! A second-order forward-mode automatic-differentiation number in N
//! variables (three by default: c₁₁, c₂₂, c₁₂): value, gradient and
//! (symmetric) Hessian carried together.
//!
//! Materials write their strain energy once, generically, as a function of the
//! in-plane right Cauchy–Green components (c₁₁, c₂₂, c₁₂); evaluating it on
//! `Hyper` numbers yields the exact stress (gradient) and tangent (Hessian), so
//! energy, stress and tangent can never disagree. Finite-difference tests check
//! them all the same.
//!
//! Every operation is inlined (`#[inline(always)]`): a `Hyper<4>` is 168
//! bytes and a `Hyper<5>` 248, and called out of line each operation
//! copied its operands and result through `memmove` — 14–18 % of a
//! solve's samples under `perf`. Inlined, the compiler keeps them in
//! registers and on the stack, and the results are bit for bit the same.

use std::ops::{Add, Div, Mul, Neg, Sub};

/// What a strain-energy formula needs of its number type. Implemented by `f64`
/// (energy only: the line search's hot path) and by [`Hyper`] (energy with exact
/// first and second derivatives), so each formula is written once.
pub trait Real:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Add<f64, Output = Self>
    + Sub<f64, Output = Self>
    + Mul<f64, Output = Self>
    + Div<f64, Output = Self>
{
    /// Whether the number carries derivatives (`Hyper`) or is a plain value
    /// (`f64`): a formula that must compute derivatives itself (the
    /// plane-stress condensation) skips them for plain values.
    const CARRIES_DERIVATIVES: bool;
    fn constant(value: f64) -> Self;
    fn value(&self) -> f64;
    fn ln(self) -> Self;
    fn sqrt(self) -> Self;
    fn powf(self, p: f64) -> Self;
    fn powi(self, n: i32) -> Self;
    /// g(self) for a scalar function g given g, g′, g″ at `self.value()`:
    /// lets a formula in one invariant apply its chain rule once.
    fn apply(self, g: f64, dg: f64, d2g: f64) -> Self;
}

impl Real for f64 {
    const CARRIES_DERIVATIVES: bool = false;
    fn constant(value: f64) -> Self {
        value
    }
    fn value(&self) -> f64 {
        *self
    }
    fn ln(self) -> Self {
        f64::ln(self)
    }
    fn sqrt(self) -> Self {
        f64::sqrt(self)
    }
    fn powf(self, p: f64) -> Self {
        f64::powf(self, p)
    }
    fn powi(self, n: i32) -> Self {
        f64::powi(self, n)
    }
    fn apply(self, g: f64, _dg: f64, _d2g: f64) -> Self {
        g
    }
}

impl<const N: usize> Real for Hyper<N> {
    const CARRIES_DERIVATIVES: bool = true;
    #[inline(always)]
    fn constant(value: f64) -> Self {
        Hyper::constant(value)
    }
    #[inline(always)]
    fn value(&self) -> f64 {
        self.value
    }
    #[inline(always)]
    fn ln(self) -> Self {
        Hyper::ln(self)
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        Hyper::sqrt(self)
    }
    #[inline(always)]
    fn powf(self, p: f64) -> Self {
        Hyper::powf(self, p)
    }
    #[inline(always)]
    fn powi(self, n: i32) -> Self {
        Hyper::powi(self, n)
    }
    #[inline(always)]
    fn apply(self, g: f64, dg: f64, d2g: f64) -> Self {
        self.chain(g, dg, d2g)
    }
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hyper<const N: usize = 3> {
    pub value: f64,
    pub gradient: [f64; N],
    pub hessian: [[f64; N]; N],
}

impl<const N: usize> Hyper<N> {
    #[inline(always)]
    pub fn constant(value: f64) -> Self {
        Hyper {
            value,
            gradient: [0.0; N],
            hessian: [[0.0; N]; N],
        }
    }

    /// The `index`-th independent variable with the given value.
    #[inline(always)]
    pub fn variable(value: f64, index: usize) -> Self {
        let mut h = Hyper::constant(value);
        h.gradient[index] = 1.0;
        h
    }

    /// g(self) given g, g′, g″ at self.value (the chain rule to second order).
    #[inline(always)]
    fn chain(self, g: f64, dg: f64, d2g: f64) -> Self {
        let mut out = Hyper::constant(g);
        for i in 0..N {
            out.gradient[i] = dg * self.gradient[i];
            for j in 0..N {
                out.hessian[i][j] =
                    dg * self.hessian[i][j] + d2g * self.gradient[i] * self.gradient[j];
            }
        }
        out
    }

    #[inline(always)]
    pub fn ln(self) -> Self {
        let x = self.value;
        self.chain(x.ln(), 1.0 / x, -1.0 / (x * x))
    }

    #[inline(always)]
    pub fn exp(self) -> Self {
        let e = self.value.exp();
        self.chain(e, e, e)
    }

    #[inline(always)]
    pub fn sqrt(self) -> Self {
        let s = self.value.sqrt();
        self.chain(s, 0.5 / s, -0.25 / (s * self.value))
    }

    #[inline(always)]
    pub fn powf(self, p: f64) -> Self {
        // One powf: xᵖ⁻¹ = xᵖ/x (x > 0 wherever a formula takes a real power).
        let x = self.value;
        let y = x.powf(p);
        let dy = p * y / x;
        self.chain(y, dy, (p - 1.0) * dy / x)
    }

    #[inline(always)]
    pub fn powi(self, n: i32) -> Self {
        let x = self.value;
        let nf = n as f64;
        self.chain(
            x.powi(n),
            nf * x.powi(n - 1),
            nf * (nf - 1.0) * x.powi(n - 2),
        )
    }
}

impl<const N: usize> Add for Hyper<N> {
    type Output = Hyper<N>;
    #[inline(always)]
    fn add(mut self, o: Hyper<N>) -> Hyper<N> {
        self.value += o.value;
        for i in 0..N {
            self.gradient[i] += o.gradient[i];
            for j in 0..N {
                self.hessian[i][j] += o.hessian[i][j];
            }
        }
        self
    }
}

impl<const N: usize> Neg for Hyper<N> {
    type Output = Hyper<N>;
    #[inline(always)]
    fn neg(self) -> Hyper<N> {
        self * -1.0
    }
}

impl<const N: usize> Sub for Hyper<N> {
    type Output = Hyper<N>;
    #[inline(always)]
    fn sub(self, o: Hyper<N>) -> Hyper<N> {
        self + (-o)
    }
}

impl<const N: usize> Mul for Hyper<N> {
    type Output = Hyper<N>;
    #[inline(always)]
    fn mul(self, o: Hyper<N>) -> Hyper<N> {
        let mut out = Hyper::constant(self.value * o.value);
        for i in 0..N {
            out.gradient[i] = self.gradient[i] * o.value + self.value * o.gradient[i];
            for j in 0..N {
                out.hessian[i][j] = self.hessian[i][j] * o.value
                    + self.value * o.hessian[i][j]
                    + self.gradient[i] * o.gradient[j]
                    + self.gradient[j] * o.gradient[i];
            }
        }
        out
    }
}

impl<const N: usize> Div for Hyper<N> {
    type Output = Hyper<N>;
    #[inline(always)]
    fn div(self, o: Hyper<N>) -> Hyper<N> {
        let x = o.value;
        self * o.chain(1.0 / x, -1.0 / (x * x), 2.0 / (x * x * x))
    }
}

impl<const N: usize> Add<f64> for Hyper<N> {
    type Output = Hyper<N>;
    #[inline(always)]
    fn add(mut self, c: f64) -> Hyper<N> {
        self.value += c;
        self
    }
}

impl<const N: usize> Sub<f64> for Hyper<N> {
    type Output = Hyper<N>;
    #[inline(always)]
    fn sub(self, c: f64) -> Hyper<N> {
        self + (-c)
    }
}

impl<const N: usize> Mul<f64> for Hyper<N> {
    type Output = Hyper<N>;
    #[inline(always)]
    fn mul(mut self, c: f64) -> Hyper<N> {
        self.value *= c;
        for i in 0..N {
            self.gradient[i] *= c;
            for j in 0..N {
                self.hessian[i][j] *= c;
            }
        }
        self
    }
}

impl<const N: usize> Div<f64> for Hyper<N> {
    type Output = Hyper<N>;
    #[inline(always)]
    fn div(self, c: f64) -> Hyper<N> {
        self * (1.0 / c)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn derivatives_of_a_composite_match_finite_differences() {
        let f = |x: [Hyper; 3]| {
            (x[0] * x[1] + x[2].exp()).ln() / x[1].sqrt() + x[0].powf(1.7) - x[2].powi(3)
        };
        let at = [1.3, 0.7, 0.4];
        let v = f([
            Hyper::variable(at[0], 0),
            Hyper::variable(at[1], 1),
            Hyper::variable(at[2], 2),
        ]);
        let scalar = |p: [f64; 3]| f(p.map(Hyper::constant)).value;
        let h = 1e-5;
        for i in 0..3 {
            let mut a = at;
            let mut b = at;
            a[i] += h;
            b[i] -= h;
            let fd = (scalar(a) - scalar(b)) / (2.0 * h);
            assert!((fd - v.gradient[i]).abs() < 1e-8, "grad {i}");
            for j in 0..3 {
                let grad_at = |p: [f64; 3]| {
                    f([
                        Hyper::variable(p[0], 0),
                        Hyper::variable(p[1], 1),
                        Hyper::variable(p[2], 2),
                    ])
                    .gradient[j]
                };
                let fd2 = (grad_at(a) - grad_at(b)) / (2.0 * h);
                assert!((fd2 - v.hessian[i][j]).abs() < 1e-6, "hess {i}{j}");
            }
        }
    }
}
