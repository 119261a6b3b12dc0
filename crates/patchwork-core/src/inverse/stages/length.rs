//! Length correction: the balloon length was chosen for the seed, and the
//! best design's patches stretch differently. Scale it once more (patch
//! positions and lengths with it, the lengths kept within the fabrication
//! limits) so the verified inflated length matches the target's, and verify
//! the corrected design.

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
        run.verified = Some(simulation);
        if (ratio - 1.0).abs() > LENGTH_TOLERANCE {
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
            let corrected = ctx
                .caches
                .simulate(&run.design, &run.setup.verify_model)
                .map_err(DesignRunError::Verify)?;
            run.verified = Some(corrected);
        }
        Ok(())
    }
}
