//! Box bounds by a smooth transformation, as pycma's `BoundTransform`: the
//! strategy searches an unbounded space; each coordinate is mapped into
//! [l, u] by a periodic reflection followed by quadratic tails of width a near
//! each bound (identity in the interior, C¹ everywhere). Evaluated points never
//! leave the box, and no penalty distorts the landscape.

use serde::{Deserialize, Serialize};

/// Per-coordinate bounds.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Bounds {
    pub lower: Vec<f64>,
    pub upper: Vec<f64>,
}

/// An impossible bound, naming the coordinate.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("bounds of variable {index}: lower {lower} must be finite and below upper {upper}")]
pub struct BoundsError {
    pub index: usize,
    pub lower: f64,
    pub upper: f64,
}

impl Bounds {
    pub fn new(lower: Vec<f64>, upper: Vec<f64>) -> Result<Bounds, BoundsError> {
        for (index, (&l, &u)) in lower.iter().zip(&upper).enumerate() {
            if !(l.is_finite() && u.is_finite() && l < u) {
                return Err(BoundsError {
                    index,
                    lower: l,
                    upper: u,
                });
            }
        }
        Ok(Bounds { lower, upper })
    }

    /// Maps a search point into the box.
    pub fn transform(&self, x: &[f64]) -> Vec<f64> {
        x.iter()
            .enumerate()
            .map(|(i, &v)| into_interval(v, self.lower[i], self.upper[i]))
            .collect()
    }
}

fn into_interval(x: f64, l: f64, u: f64) -> f64 {
    let al = ((u - l) / 2.0).min((1.0 + l.abs()) / 20.0);
    let au = ((u - l) / 2.0).min((1.0 + u.abs()) / 20.0);
    // Reflect periodically into [l − al, u + au].
    let (lo, hi) = (l - al, u + au);
    let width = hi - lo;
    let mut y = (x - lo).rem_euclid(2.0 * width);
    if y > width {
        y = 2.0 * width - y;
    }
    let y = lo + y;
    if y < l + al {
        l + (y - lo).powi(2) / (4.0 * al)
    } else if y > u - au {
        u - (y - hi).powi(2) / (4.0 * au)
    } else {
        y
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn transform_stays_inside_is_identity_inside_and_continuous() {
        let b = Bounds::new(vec![1.0, -5.0], vec![3.0, 5.0]).unwrap();
        let mut previous = b.transform(&[-20.0, -20.0]);
        for k in 0..4000 {
            let x = -20.0 + 0.01 * k as f64;
            let y = b.transform(&[x, x]);
            for (v, (l, u)) in y.iter().zip(b.lower.iter().zip(&b.upper)) {
                assert!(*l <= *v && *v <= *u);
            }
            assert!((y[0] - previous[0]).abs() <= 0.0101 && (y[1] - previous[1]).abs() <= 0.0101);
            previous = y;
        }
        assert_eq!(b.transform(&[2.0, 0.0]), vec![2.0, 0.0]);
        assert!(Bounds::new(vec![1.0], vec![1.0]).is_err());
        assert!(Bounds::new(vec![f64::NAN], vec![1.0]).is_err());
    }
}
