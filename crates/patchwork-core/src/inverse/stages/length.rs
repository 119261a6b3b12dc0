//! Length correction: the balloon length was chosen for the seed, and the
//! best design's patches stretch differently. Scale it once more (patch
//! positions and lengths with it, the lengths kept within the fabrication
//! limits) so the verified inflated length matches the target's, and verify
//! the corrected design, warm-started from the state before the stretch.

use super::super::errors::DesignRunError;
use super::super::run::{Context, Run};

/// Relative mismatch of inflated and target length left uncorrected.
const LENGTH_TOLERANCE: f64 = 1e-3;

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Length;

impl Length {
    pub(in super::super) fn run(
        &self,
        run: &mut Run<'_>,
        ctx: &mut Context<'_>,
    ) -> Result<(), DesignRunError> {
        let simulation = run.take_verified("length correction")?;
        let ratio = run.setup.target.length() / simulation.inflated_length_mm;
        if (ratio - 1.0).abs() <= LENGTH_TOLERANCE {
            run.verified = Some(simulation);
            return Ok(());
        }
        let bounds = &run.setup.settings.bounds;
        let within: Vec<bool> = run
            .design
            .patches
            .iter()
            .map(|p| bounds.holds_size(p))
            .collect();
        run.design.stretch_length(ratio);
        for (patch, within) in run.design.patches.iter_mut().zip(within) {
            if within {
                *patch = bounds.size_within(patch);
            }
        }
        // From the state before the stretch, carried onto the new mesh (the
        // cold start if that fails): the Hilbert curve's solve takes 0.2 s
        // instead of 0.4 s from the cold start, every curve of the suite
        // 0.0–0.1 s less, the designs and their shape errors as before
        // (docs/studies.md).
        let model = &run.setup.verify_model;
        let corrected = (ctx.caches)
            .simulate_from(&run.design, model, Some(&simulation))
            .or_else(|_| ctx.caches.simulate(&run.design, model));
        // On failure the unstretched state stays verified, as before the stage.
        let (verified, outcome) = match corrected {
            Ok(corrected) => (corrected, Ok(())),
            Err(error) => (simulation, Err(DesignRunError::Verify(error))),
        };
        run.verified = Some(verified);
        outcome
    }
}
