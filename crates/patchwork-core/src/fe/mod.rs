//! The forward model: a nonlinear finite-element model of the inflating,
//! patch-clad membrane tube, and the centreline it takes.
//!
//! `simulate(design, options)` meshes the balloon, starts Newton from the
//! closed-form bare-tube state at the design pressure (above the bare tube's
//! pressure plateau, on its stable rising branch — no need to trace the whole
//! inflation through the bulge), then lets the patched regions relax by
//! continuation in patch stiffness with automatic step control.
//!
//! Not modelled: gravity, self-contact (a knot passes through itself; `contact`
//! finds where the predicted shape does), inflation dynamics, wall-thickness
//! variation of real balloons, bending stiffness.

mod assembly;
mod carry;
pub mod centreline;
pub mod contact;
mod continuation;
pub mod element;
pub mod export;
pub mod grading;
pub mod kinematic;
pub mod laminate;
pub mod mesh;
pub mod model;
pub mod newton;
pub mod overlap;
pub mod pressure;
mod reflect;
pub mod ring_step;
pub mod section;
pub mod sensitivity;
mod simulate;
mod tangent_factor;
pub mod tube_theory;
pub mod volume_control;

pub use reflect::{reflected_start, second_order_start};
pub use simulate::{
    SimulateError, SimulateOptions, Simulation, simulate, simulate_from, simulate_with,
};
