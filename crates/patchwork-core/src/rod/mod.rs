//! A reduced-order model of the inflated balloon: a rod whose centreline is
//! integrated from the clamp, each patch bending, twisting and shortening
//! it over its axial extent by amounts fitted to FE solves of that patch
//! alone (`table.rs`, `fit.rs`), the bare tube stretching as an FE bare
//! balloon does, its ends included (`bare.rs`). It answers in microseconds
//! where an FE solve takes a fraction of a second, and is as good as its
//! table: how close it comes to FE on designs of many patches is measured
//! in docs/studies.md ("A rod model for the search").
//!
//! Along the uninflated height y, with R₀ the balloon's radius and each
//! patch p (centre Xₚ, Yₚ, axial half-extent aₚ) covering
//! |y − Yₚ| ≤ aₚ:
//!
//! ```text
//! λ(y) = λ_bare(y) + Σₚ Δλₚ                      axial stretch of the centreline
//! k(y) = Σₚ κₚ (cos φₚ(y), sin φₚ(y), 0)          curvature vector in the section's axes
//! φₚ(y) = Xₚ/R₀ + φ₀ₚ + τₚ (y − Yₚ)               the side the patch bends towards
//! dc/dy = λ(y) t,   dF/dy = F [ẑ × k(y)]ₓ           centre c, section frame F (t = F ẑ)
//! ```
//!
//! (κ and τ per uninflated millimetre). The frame turns about ẑ × k only: the
//! rod carries no material twist between patches. What a patch's
//! neighbours do to it is not in the table; an FE solve of a whole design
//! measures it per patch (`correction.rs`), for designs near that one.

mod bare;
mod correction;
mod fit;
mod integrate;
mod table;

pub use bare::BareTube;
pub use correction::{Correction, fit_corrections};
pub use fit::fit_patch;
pub use integrate::{PatchRod, Placed, centres};
pub use table::{RodTable, axes};
