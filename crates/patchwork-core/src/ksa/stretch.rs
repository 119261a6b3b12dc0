use super::KsaError;

/// How KSA maps deformed (target) lengths back to the uninflated balloon.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Stretch {
    /// The authors' assumption: uniform λ = L_curve / L₀. Their own code calls it
    /// "not physically true": patches stretch less than bare wall (on the
    /// reference balloon at 20 kPa the bare tube stretches 3.67 axially, the
    /// patched stretches less, so their curves of 3.1 × L₀ fit).
    Uniform,
    /// A given axial stretch, e.g. from the membrane solution of the bare tube.
    /// The balloon to cut is then `L_curve / λ` long, not `L₀`.
    Fixed(f64),
}

impl Stretch {
    pub(super) fn value(&self, curve_length: f64, l0: f64) -> f64 {
        match self {
            Stretch::Uniform => curve_length / l0,
            Stretch::Fixed(lambda) => *lambda,
        }
    }

    pub(super) fn validate(&self) -> Result<(), KsaError> {
        match self {
            Stretch::Fixed(lambda) if !(lambda.is_finite() && *lambda > 0.0) => Err(KsaError {
                name: "stretch",
                value: *lambda,
                reason: "must be finite and positive",
            }),
            _ => Ok(()),
        }
    }
}
