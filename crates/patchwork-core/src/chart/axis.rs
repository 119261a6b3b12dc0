//! A chart axis: its range widened to round numbers, its ticks and their
//! labels, on a linear or a logarithmic scale.

/// How values map onto an axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Scale {
    Linear,
    /// Base 10; every value must be positive.
    Log,
}

/// An axis from `lo` to `hi` with a label that names the quantity and unit.
#[derive(Debug, Clone, PartialEq)]
pub struct Axis {
    pub label: String,
    pub scale: Scale,
    lo: f64,
    hi: f64,
    /// Distance between labelled ticks (linear), in the axis' unit.
    step: f64,
}

/// Labelled ticks a linear axis aims at.
const TICKS: f64 = 5.0;

impl Axis {
    /// A linear axis covering `values` (non-finite ones ignored), widened to
    /// a multiple of a round step (1, 2 or 5 × 10ⁿ); `0..1` when there is
    /// nothing to cover, and a unit around a single value.
    pub fn linear(label: &str, values: impl IntoIterator<Item = f64>) -> Axis {
        let (lo, hi) = finite_range(values).unwrap_or((0.0, 1.0));
        let (lo, hi) = match hi > lo {
            true => (lo, hi),
            false => (lo - 0.5 * lo.abs().max(1.0), hi + 0.5 * hi.abs().max(1.0)),
        };
        let step = round_step((hi - lo) / TICKS);
        Axis {
            label: label.into(),
            scale: Scale::Linear,
            lo: (lo / step).floor() * step,
            hi: (hi / step).ceil() * step,
            step,
        }
    }

    /// A logarithmic axis covering the positive `values`, widened to whole
    /// decades.
    pub fn log(label: &str, values: impl IntoIterator<Item = f64>) -> Axis {
        let positive = values.into_iter().filter(|v| *v > 0.0);
        let (lo, hi) = finite_range(positive).unwrap_or((1.0, 10.0));
        let (lo, hi) = (lo.log10().floor(), hi.log10().ceil());
        Axis {
            label: label.into(),
            scale: Scale::Log,
            lo: 10f64.powf(lo),
            hi: 10f64.powf(hi.max(lo + 1.0)),
            step: 1.0,
        }
    }

    /// Where `value` lies along the axis, 0 at its start and 1 at its end.
    pub fn fraction(&self, value: f64) -> f64 {
        match self.scale {
            Scale::Linear => (value - self.lo) / (self.hi - self.lo),
            Scale::Log => {
                (value.max(f64::MIN_POSITIVE).log10() - self.lo.log10())
                    / (self.hi.log10() - self.lo.log10())
            }
        }
    }

    /// The value at `fraction` along the axis (the inverse of
    /// [`Axis::fraction`]).
    pub fn value_at(&self, fraction: f64) -> f64 {
        match self.scale {
            Scale::Linear => self.lo + fraction * (self.hi - self.lo),
            Scale::Log => {
                10f64.powf(self.lo.log10() + fraction * (self.hi.log10() - self.lo.log10()))
            }
        }
    }

    /// The labelled ticks: every step (linear) or every decade (log).
    pub fn ticks(&self) -> Vec<f64> {
        match self.scale {
            Scale::Linear => {
                let n = ((self.hi - self.lo) / self.step).round() as i64;
                (0..=n).map(|k| self.lo + k as f64 * self.step).collect()
            }
            Scale::Log => {
                let (a, b) = (self.lo.log10().round(), self.hi.log10().round());
                (a as i64..=b as i64)
                    .map(|k| 10f64.powi(k as i32))
                    .collect()
            }
        }
    }

    /// Unlabelled ticks between the labelled ones: 2–9 × each decade (log),
    /// none on a linear axis.
    pub fn minor_ticks(&self) -> Vec<f64> {
        match self.scale {
            Scale::Linear => vec![],
            Scale::Log => self
                .ticks()
                .iter()
                .flat_map(|decade| (2..10).map(move |k| k as f64 * decade))
                .filter(|v| *v < self.hi)
                .collect(),
        }
    }

    /// A tick's label: as many decimals as the step needs, no `-0`.
    pub fn tick_label(&self, value: f64) -> String {
        let step = match self.scale {
            Scale::Linear => self.step,
            Scale::Log => value,
        };
        let decimals = (-step.log10().floor()).max(0.0) as usize;
        let text = format!("{value:.decimals$}");
        match text
            .trim_start_matches('-')
            .chars()
            .all(|c| c == '0' || c == '.')
        {
            true => text.trim_start_matches('-').to_string(),
            false => text,
        }
    }
}

fn finite_range(values: impl IntoIterator<Item = f64>) -> Option<(f64, f64)> {
    values
        .into_iter()
        .filter(|v| v.is_finite())
        .fold(None, |range, v| match range {
            None => Some((v, v)),
            Some((lo, hi)) => Some((v.min(lo), v.max(hi))),
        })
}

/// The round number (1, 2 or 5 × 10ⁿ) nearest above `rough`.
fn round_step(rough: f64) -> f64 {
    let decade = 10f64.powf(rough.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * decade)
        .find(|step| *step >= rough * (1.0 - 1e-9))
        .unwrap_or(10.0 * decade)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_linear_axis_widens_to_round_ticks() {
        let axis = Axis::linear("κ (1/mm)", [0.003, 0.047]);
        assert_eq!(axis.ticks().len(), 6);
        assert_eq!(axis.ticks()[0], 0.0);
        assert!((axis.ticks()[5] - 0.05).abs() < 1e-12);
        assert_eq!(axis.tick_label(axis.ticks()[1]), "0.01");
        assert!((axis.fraction(0.025) - 0.5).abs() < 1e-12);
    }

    #[test]
    fn negative_values_get_ticks_below_zero_without_minus_zero() {
        let axis = Axis::linear("τ (1/mm)", [-0.012, 0.031]);
        let ticks = axis.ticks();
        assert_eq!(ticks[0], -0.02);
        assert!(ticks.iter().any(|t| axis.tick_label(*t) == "0.00"));
        assert!(!ticks.iter().any(|t| axis.tick_label(*t) == "-0.00"));
    }

    #[test]
    fn a_log_axis_spans_whole_decades() {
        let axis = Axis::log("s", [3.0, 140.0, f64::NAN, -1.0]);
        assert_eq!(axis.ticks(), vec![1.0, 10.0, 100.0, 1000.0]);
        assert_eq!(axis.tick_label(1000.0), "1000");
        assert_eq!(axis.tick_label(0.1), "0.1");
        assert!((axis.fraction(10.0) - 1.0 / 3.0).abs() < 1e-12);
        assert_eq!(axis.minor_ticks().len(), 3 * 8);
    }

    #[test]
    fn empty_and_constant_data_still_give_an_axis() {
        assert_eq!(Axis::linear("x", []).ticks().len(), 6);
        let flat = Axis::linear("x", [2.0, 2.0]);
        assert!(flat.fraction(2.0) > 0.0 && flat.fraction(2.0) < 1.0);
    }
}
