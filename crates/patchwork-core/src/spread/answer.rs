//! What a spread answers: the centreline's spread, the tip's band, the
//! expected shape error against the target, and every source's share,
//! largest first.

use serde::{Deserialize, Serialize};

use super::sources::Source;

/// One source's share of the spread.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Contributor {
    #[serde(flatten)]
    pub source: Source,
    /// "P3 angle".
    pub label: String,
    /// Its tolerance, in `unit`.
    pub tolerance: f64,
    pub unit: String,
    /// The centreline's RMS change at the tolerance (mm, after the best
    /// rigid alignment).
    pub rms_mm: f64,
    /// How far the tip moves at the tolerance, in the clamp's frame (mm).
    pub tip_mm: f64,
    /// The RMS of the centreline's mean move under this source alone (mm;
    /// 0 unless solved both ways): the response's even part, which moves
    /// the expected centreline off the nominal one.
    #[serde(default)]
    pub shift_mm: f64,
    /// How the change was found (a result written before this field: solved).
    #[serde(default)]
    pub estimate: Estimate,
}

/// How a source's change was found.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Estimate {
    /// A Newton solve of the design with the source at its tolerance, one
    /// way only (its solve at −tolerance failed, or a result written
    /// before sources were solved both ways).
    #[default]
    Solved,
    /// The linearised response at the nominal state (a source under
    /// `SOLVED_FRACTION` of the largest).
    Linearised,
    /// Newton solves at +tolerance and at −tolerance: the change's odd and
    /// even parts (`change.rs`).
    BothWays,
    /// The equivalent source's change read at this one's tolerance: the
    /// balloon's modulus and its wall thickness act as one
    /// ([`Source::equivalent`](super::Source::equivalent)), so the source
    /// of the two with the smaller tolerance takes the other's odd and
    /// even parts, scaled (`change.rs`).
    Equivalent,
    /// Found with the balloon's other sources that act as one (the wall,
    /// the modulus and, where its move lies along theirs, the pressure):
    /// their change together by quadrature on their joint variable, this
    /// source's share of it shown (`balloon.rs`).
    Combined,
}

/// What the samples found.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MonteCarlo {
    pub samples: usize,
    pub seed: u64,
    /// Samples whose design did not solve (left out of the figures).
    pub failed: usize,
    /// The centreline's RMS change over the samples that solved (mm), and
    /// the tip's RMS distance from its nominal place.
    pub rms_mm: f64,
    pub tip_rms_mm: f64,
    /// `rms_mm` over the linear spread's, and its sampling error (one σ).
    pub ratio: f64,
    pub ratio_sigma: f64,
    /// The ratio within `AGREEMENT` (`monte_carlo.rs`) of 1.
    pub agrees: bool,
}

/// The linear spread of a design's centreline.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Spread {
    /// RMS of the centreline's change from the nominal, all sources
    /// together (in quadrature, plus the sources' mean moves added as
    /// vectors), mm and % of the length.
    pub rms_mm: f64,
    pub rms_percent: f64,
    /// Every source at its tolerance the worst way (their changes added in
    /// magnitude: an upper bound), mm.
    pub worst_mm: f64,
    /// The tip's RMS distance from its nominal place (clamp's frame), mm;
    /// and its worst case (added in magnitude).
    pub tip_rms_mm: f64,
    pub tip_worst_mm: f64,
    /// The nominal and the expected shape error against the target (RMS
    /// over the spread: √(nominal² + spread²)), % of the target's length;
    /// absent without a target.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub nominal_shape_error_percent: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub expected_shape_error_percent: Option<f64>,
    /// The RMS distance (mm) of the expected centreline from the nominal:
    /// the sources' mean moves added up (the part of `rms_mm` that is not
    /// scatter about the expected shape, but an offset of it).
    #[serde(default)]
    pub mean_shift_mm: f64,
    /// Every source, the largest share first.
    pub contributors: Vec<Contributor>,
    /// FE solves taken: one or two per source solved, one for the linearised
    /// responses of all (a factorisation of the nominal's tangent), and the
    /// nominal where it was solved for the spread (not in a design run,
    /// which has it).
    pub solves: usize,
    /// The Monte-Carlo check, where one was asked for.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub monte_carlo: Option<MonteCarlo>,
    /// The band along the centreline: at each of `SAMPLES` equal fractions
    /// of its length from the base, the RMS distance (mm) the point moves
    /// over every source (in quadrature, after the best rigid alignment, as
    /// `rms_mm` is measured: its mean square is `rms_mm`²).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub band_mm: Vec<f64>,
}

impl Spread {
    /// This spread with the nominal design's shape error against the
    /// target set to `nominal_percent`, and the expected one from it.
    pub fn against_given(mut self, nominal_percent: f64) -> Spread {
        self.nominal_shape_error_percent = Some(nominal_percent);
        self.expected_shape_error_percent = Some(nominal_percent.hypot(self.rms_percent));
        self
    }

    /// The patches (numbered from 1, in order) among the `n` largest
    /// contributors: the ones to place with most care.
    pub fn careful_patches(&self, n: usize) -> Vec<usize> {
        let mut patches: Vec<usize> = self
            .contributors
            .iter()
            .take(n)
            .filter_map(|c| match c.source {
                Source::Patch { patch, .. } => Some(patch),
                _ => None,
            })
            .collect();
        patches.sort_unstable();
        patches.dedup();
        patches
    }

    /// The `n` largest contributors as a person reads them: "P3 angle ±2°:
    /// 1.20 mm RMS, tip 2.10 mm".
    pub fn largest(&self, n: usize) -> Vec<String> {
        self.contributors
            .iter()
            .take(n)
            .map(|c| {
                let gap = if c.unit == "°" { "" } else { " " };
                format!(
                    "{} ±{}{gap}{}: {:.2} mm RMS, tip {:.2} mm",
                    c.label, c.tolerance, c.unit, c.rms_mm, c.tip_mm
                )
            })
            .collect()
    }
}
