//! The bare tube's axial stretch along the balloon: uniform far from the
//! ends, lower near the clamp (whose ring keeps the uninflated radius) and
//! near the cap, as an FE solve of a bare balloon has it.

use serde::{Deserialize, Serialize};

use crate::fe::centreline::Ring;

/// The bare tube's stretch: `stretch` far from the ends, and the stretch
/// of successive intervals of `step` (uninflated mm) from the clamp and
/// from the cap, out to the middle of the balloon it was measured on; and
/// its inflated radius far from the ends (mm).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BareTube {
    pub radius: f64,
    pub stretch: f64,
    pub step: f64,
    pub from_clamp: Vec<f64>,
    pub from_cap: Vec<f64>,
}

impl BareTube {
    /// The same stretch everywhere (no ends), of no radius.
    pub fn uniform(stretch: f64) -> BareTube {
        BareTube {
            radius: 0.0,
            stretch,
            step: 1.0,
            from_clamp: Vec::new(),
            from_cap: Vec::new(),
        }
    }

    /// From the rings of an FE bare balloon at equal material spacing: each
    /// interval's centre-to-centre distance over its uninflated length; the
    /// stretch far from the ends is the middle interval's. None if there are
    /// fewer than four rings.
    pub fn from_rings(rings: &[Ring]) -> Option<BareTube> {
        if rings.len() < 4 {
            return None;
        }
        let intervals: Vec<f64> = rings
            .windows(2)
            .map(|w| (w[1].centre - w[0].centre).norm() / (w[1].y - w[0].y))
            .collect();
        let half = intervals.len() / 2;
        Some(BareTube {
            radius: rings[rings.len() / 2].radius,
            stretch: intervals[half],
            step: rings[1].y - rings[0].y,
            from_clamp: intervals[..half].to_vec(),
            from_cap: intervals[intervals.len() - half..]
                .iter()
                .rev()
                .copied()
                .collect(),
        })
    }

    /// The bare stretch at height `y` of a balloon of `length`: each end's
    /// profile as a factor on the far stretch.
    pub fn at(&self, y: f64, length: f64) -> f64 {
        let clamp = profile(&self.from_clamp, self.step, y, self.stretch);
        let cap = profile(&self.from_cap, self.step, length - y, self.stretch);
        clamp * cap / self.stretch
    }
}

/// `values[k]` holds over [k·step, (k + 1)·step) from the end; `far` beyond.
fn profile(values: &[f64], step: f64, distance: f64, far: f64) -> f64 {
    let k = (distance / step).floor();
    if k < 0.0 {
        return values.first().copied().unwrap_or(far);
    }
    values.get(k as usize).copied().unwrap_or(far)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::curve::Point;

    #[test]
    fn the_ends_lower_the_stretch_and_the_middle_is_far() {
        // Rings every 1 mm of a 10 mm balloon: centres 1, 2, 3, 3, 3, ...
        // apart, the last interval 2.
        let gaps = [1.0, 2.0, 3.0, 3.0, 3.0, 3.0, 3.0, 3.0, 3.0, 2.0];
        let mut z = 0.0;
        let mut rings = vec![Ring {
            y: 0.0,
            centre: Point::zeros(),
            radius: 1.0,
        }];
        for (k, g) in gaps.iter().enumerate() {
            z += g;
            rings.push(Ring {
                y: (k + 1) as f64,
                centre: Point::new(0.0, 0.0, z),
                radius: 1.0,
            });
        }
        let bare = BareTube::from_rings(&rings).unwrap();
        assert_eq!(bare.stretch, 3.0);
        assert_eq!(bare.at(0.5, 100.0), 1.0);
        assert_eq!(bare.at(1.5, 100.0), 2.0);
        assert_eq!(bare.at(50.0, 100.0), 3.0);
        assert_eq!(bare.at(99.5, 100.0), 2.0);
    }
}
