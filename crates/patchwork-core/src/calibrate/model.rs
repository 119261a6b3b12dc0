//! What the FE model predicts for a bare balloon inflated: its length from
//! the clamp to the cap's pole (the inflated centreline plus the cap), its
//! diameter across the middle (twice the mid ring's fitted radius,
//! mid-wall) and the volume its mid-surface encloses, at each pressure.
//!
//! The volume is the smooth balloon's through the rings the diameter is
//! read from: V = ∫ π r² ds along the centreline (trapezoids in r²) plus
//! the cap as a spherical segment on the last ring, π h (3a² + h²)/6. The
//! mesh's own enclosed volume is that of flat facets (the polygon of a
//! ring's nodes has sin(2π/n)/(2π/n) of its circle's area: 0.4 % less at
//! the 40 nodes around of the default mesh); a measured volume is of the
//! round balloon.
//!
//! Every solve is on [`MeshSpec::default_simulation`], the mesh `simulate`
//! uses and a design's prediction is corrected to: calibrated on a coarser
//! one, the parameters would absorb its error (a 2 mm mesh's patched
//! centrelines lie up to 1.7 % of the length from a fine solution).

use std::f64::consts::PI;

use crate::design::{Balloon, Design};
use crate::fe::mesh::MeshSpec;
use crate::fe::{SimulateOptions, Simulation, simulate_from};

/// The bare balloon at one pressure.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bare {
    pub length_mm: f64,
    pub diameter_mm: f64,
    pub volume_ml: f64,
}

/// The bare `balloon` inflated to `pressure_kpa`, warm-started from
/// `previous` where given; none where the model cannot inflate it (no
/// stable state at that pressure). A calibration starts every bare solve
/// cold: the closed-form tube is a closer start than another material's
/// state (warm-started from the starting material's, a fit of four
/// pressures took 3.5 times as long).
pub fn bare_state(
    balloon: &Balloon,
    pressure_kpa: f64,
    previous: Option<&Simulation>,
) -> Option<Simulation> {
    let design = Design {
        balloon: balloon.clone(),
        pressure_kpa,
        ..Design::reference(Vec::new())
    };
    simulate_from(&design, &options(), previous).ok()
}

/// What a lab measures of the bare balloon in `sim`.
pub fn bare(sim: &Simulation) -> Option<Bare> {
    let mid = &sim.rings[sim.rings.len() / 2];
    Some(Bare {
        length_mm: sim.inflated_length_mm + sim.cap_height()?,
        diameter_mm: 2.0 * mid.radius,
        volume_ml: round_volume_mm3(sim)? / 1000.0,
    })
}

/// The model every calibration solve runs, its assemblies on every core:
/// a fit of one or two parameters solves mostly one balloon at a time (the
/// same answer for any thread count).
pub fn options() -> SimulateOptions {
    SimulateOptions {
        mesh: MeshSpec::default_simulation(),
        threads: crate::available_cores(),
        ..SimulateOptions::default()
    }
}

/// The volume of the round balloon through `sim`'s rings and its cap (mm³).
pub fn round_volume_mm3(sim: &Simulation) -> Option<f64> {
    let s = sim.centreline.arc_length();
    let tube: f64 = (1..sim.rings.len())
        .map(|i| {
            let (a, b) = (sim.rings[i - 1].radius, sim.rings[i].radius);
            PI * 0.5 * (a * a + b * b) * (s[i] - s[i - 1])
        })
        .sum();
    let (a, h) = (sim.rings.last()?.radius, sim.cap_height()?.max(0.0));
    Some(tube + PI * h * (3.0 * a * a + h * h) / 6.0)
}
