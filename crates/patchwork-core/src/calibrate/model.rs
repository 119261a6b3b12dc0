//! What the FE model predicts for a bare balloon inflated: its length from
//! the clamp to the cap's pole (the inflated centreline plus the cap) and
//! its diameter across the middle (twice the mid ring's fitted radius,
//! mid-wall), at each pressure.

use super::Inflation;
use crate::design::{Balloon, Design};
use crate::fe::{SimulateOptions, simulate};

/// One measured quantity and what the model says of it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Predicted {
    pub length_mm: f64,
    pub diameter_mm: f64,
}

/// The bare `balloon` inflated to each pressure of `data`; none where the
/// model cannot inflate it (no stable state at that pressure).
pub fn predict(balloon: &Balloon, data: &[Inflation]) -> Option<Vec<Predicted>> {
    data.iter()
        .map(|d| {
            let design = Design {
                balloon: balloon.clone(),
                pressure_kpa: d.pressure_kpa,
                ..Design::reference(Vec::new())
            };
            let sim = simulate(&design, &SimulateOptions::default()).ok()?;
            let mid = &sim.rings[sim.rings.len() / 2];
            Some(Predicted {
                length_mm: sim.inflated_length_mm + sim.cap_height()?,
                diameter_mm: 2.0 * mid.radius,
            })
        })
        .collect()
}

/// The relative misfit of every measured quantity: predicted / measured − 1,
/// lengths then diameters in the data's order.
pub fn residuals(data: &[Inflation], predicted: &[Predicted]) -> Vec<f64> {
    let mut r = Vec::new();
    for (d, p) in data.iter().zip(predicted) {
        if let Some(length) = d.length_mm {
            r.push(p.length_mm / length - 1.0);
        }
        if let Some(diameter) = d.diameter_mm {
            r.push(p.diameter_mm / diameter - 1.0);
        }
    }
    r
}
