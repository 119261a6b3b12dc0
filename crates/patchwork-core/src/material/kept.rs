//! Where an element's thickness solves start: what they found last time.
//!
//! Every evaluation of a compressible layer solves for its thickness: the
//! ln J at which σ₃₃ = 0 ([`super::thickness`]), a root that is unique (W is
//! convex in ln J), so where its Newton starts changes the iterations, not
//! the answer. Newton's iterations on a model move its states by small
//! steps, so the ln J an element's layer found at the last evaluation is
//! close to the one its next evaluation needs: started there, the solve
//! converges in two or three steps instead of four to six from J = 1.
//! (A cut element's jump α is not kept: its Φ need not be convex in α, and
//! a start other than the Voigt state may find another minimum.)
//!
//! The answers are kept per element as atomic f64s: a model's triangles are
//! assembled on several threads, each triangle by one, so the sequence of
//! evaluations each element sees, and with it every bit of the result, does
//! not depend on the thread count. A model whose elements several threads
//! evaluate at once (the sensitivity's base model) keeps none.

use std::sync::atomic::{AtomicU64, Ordering};

/// The last answer of one inner solve: `N` numbers, zero before any.
#[derive(Debug)]
pub struct Kept<const N: usize>([AtomicU64; N]);

impl<const N: usize> Default for Kept<N> {
    fn default() -> Self {
        Kept(std::array::from_fn(|_| AtomicU64::new(0)))
    }
}

impl<const N: usize> Kept<N> {
    /// The kept numbers.
    pub fn get(&self) -> [f64; N] {
        self.0
            .each_ref()
            .map(|a| f64::from_bits(a.load(Ordering::Relaxed)))
    }

    /// Keeps `values` for the next solve.
    pub fn set(&self, values: [f64; N]) {
        for (slot, value) in self.0.iter().zip(values) {
            slot.store(value.to_bits(), Ordering::Relaxed);
        }
    }
}

impl<const N: usize> Clone for Kept<N> {
    fn clone(&self) -> Self {
        let copy = Kept::default();
        copy.set(self.get());
        copy
    }
}

/// Where a solve starts is not part of what an element is: two elements
/// are equal whatever they keep.
impl<const N: usize> PartialEq for Kept<N> {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

/// One kept start per material of a layer stack (indexed as its layers'
/// `material`); empty: the stack keeps none.
pub type KeptPerMaterial = Vec<Kept<1>>;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kept_numbers_are_read_back_and_cloned() {
        let kept = Kept::<2>::default();
        assert_eq!(kept.get(), [0.0, 0.0]);
        kept.set([0.25, -1.5e-3]);
        assert_eq!(kept.clone().get(), [0.25, -1.5e-3]);
        assert!(kept == Kept::default());
    }
}
