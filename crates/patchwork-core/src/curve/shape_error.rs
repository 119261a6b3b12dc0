//! Shape error: how far one centreline is from another, after the best rigid
//! alignment. The number a person reads to judge a design.

use nalgebra::{Matrix3, Rotation3};

use super::{Curve, CurveError, Point};

/// Result of [`shape_error`].
#[derive(Debug, Clone, PartialEq)]
pub struct ShapeError {
    /// Root-mean-square distance between corresponding samples (mm).
    pub rms_mm: f64,
    /// `rms_mm` as a percentage of the target's length.
    pub percent_of_length: f64,
    /// The rotation that, with `translation`, maps `achieved` onto `target`.
    pub rotation: Rotation3<f64>,
    pub translation: Point,
}

/// Resamples both curves to `samples` points by arc length (so a 10 % longer
/// curve is compared point-for-point at equal *fractions* of length), finds the
/// rigid motion minimising the RMS distance (Kabsch, with the reflection guard),
/// and reports that RMS.
pub fn shape_error(
    achieved: &Curve,
    target: &Curve,
    samples: usize,
) -> Result<ShapeError, CurveError> {
    let aligned = AlignedSamples::new(achieved, &target.resample(samples)?)?;
    let sum_sq: f64 = aligned.residuals.iter().map(|r| r.norm_squared()).sum();
    let rms_mm = (sum_sq / samples as f64).sqrt();
    Ok(ShapeError {
        rms_mm,
        percent_of_length: 100.0 * rms_mm / target.length(),
        rotation: aligned.rotation,
        translation: aligned.translation,
    })
}

/// `achieved` resampled like `target_samples` and rigidly aligned onto them:
/// the residual rᵢ = R aᵢ + t − bᵢ of every sample (mm), so that the shape
/// error is √(Σ|rᵢ|²/n). The refine's least-squares residuals.
#[derive(Debug, Clone, PartialEq)]
pub struct AlignedSamples {
    pub residuals: Vec<Point>,
    pub rotation: Rotation3<f64>,
    pub translation: Point,
}

impl AlignedSamples {
    /// `target_samples` is the target already resampled (once, by the caller).
    pub fn new(achieved: &Curve, target_samples: &Curve) -> Result<AlignedSamples, CurveError> {
        let a = achieved.resample(target_samples.len())?;
        let b = target_samples;
        let (rotation, translation) = kabsch(a.points(), b.points());
        let residuals = a
            .points()
            .iter()
            .zip(b.points())
            .map(|(p, q)| rotation * p + translation - q)
            .collect();
        Ok(AlignedSamples {
            residuals,
            rotation,
            translation,
        })
    }
}

/// The proper rotation R and translation t minimising Σ |R pᵢ + t − qᵢ|²
/// (Kabsch). Also used to read a ring's rotation off two FE solutions.
pub fn kabsch(p: &[Point], q: &[Point]) -> (Rotation3<f64>, Point) {
    let n = p.len() as f64;
    let p_mean = p.iter().sum::<Point>() / n;
    let q_mean = q.iter().sum::<Point>() / n;
    let mut h = Matrix3::zeros();
    for (pi, qi) in p.iter().zip(q) {
        h += (pi - p_mean) * (qi - q_mean).transpose();
    }
    let svd = h.svd(true, true);
    let rotation = match (svd.u, svd.v_t) {
        (Some(u), Some(v_t)) => {
            let v = v_t.transpose();
            let d = (v * u.transpose()).determinant().signum();
            let correction = Matrix3::from_diagonal(&Point::new(1.0, 1.0, d));
            Rotation3::from_matrix_unchecked(v * correction * u.transpose())
        }
        _ => Rotation3::identity(),
    };
    let translation = q_mean - rotation * p_mean;
    (rotation, translation)
}

/// Bend angle and twist about the z axis (degrees) of the best-fit rotation
/// taking `reference` points (a cross-section ring) to `deformed`: the bend is
/// the angle between the rotated and the original z axis, the twist the
/// swing–twist decomposition's angle about z.
pub fn bend_and_twist(reference: &[Point], deformed: &[Point]) -> (f64, f64) {
    let (rotation, _) = kabsch(reference, deformed);
    let r = rotation.matrix();
    let bend = r[(2, 2)].clamp(-1.0, 1.0).acos().to_degrees();
    let w = (1.0 + r.trace()).max(0.0).sqrt() / 2.0;
    let z = (r[(1, 0)] - r[(0, 1)]) / (4.0 * w);
    (bend, (2.0 * z.atan2(w)).to_degrees())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::curve::presets::{ArcParams, LineParams, Preset};

    #[test]
    fn rigidly_moved_curve_has_zero_error() {
        let helix = Preset::helix(20.0, 40.0, 2.0).generate(300).unwrap();
        let rotation = Rotation3::from_euler_angles(0.3, -1.1, 2.0);
        let moved = helix.transformed(&rotation, &Point::new(5.0, -7.0, 100.0));
        let e = shape_error(&moved, &helix, 200).unwrap();
        assert!(e.rms_mm < 1e-9, "{}", e.rms_mm);
    }

    #[test]
    fn aligned_residuals_are_the_shape_error_sample_by_sample() {
        let helix = Preset::helix(20.0, 40.0, 2.0).generate(300).unwrap();
        let wider = Preset::helix(21.0, 40.0, 2.0).generate(250).unwrap();
        let e = shape_error(&wider, &helix, 200).unwrap();
        let aligned = AlignedSamples::new(&wider, &helix.resample(200).unwrap()).unwrap();
        let rms = (aligned
            .residuals
            .iter()
            .map(|r| r.norm_squared())
            .sum::<f64>()
            / 200.0)
            .sqrt();
        assert_eq!(aligned.residuals.len(), 200);
        assert!(e.rms_mm > 0.1 && (rms - e.rms_mm).abs() < 1e-12 * e.rms_mm);
    }

    #[test]
    fn mirror_image_is_not_aligned_by_a_reflection() {
        let helix = Preset::helix(20.0, 40.0, 2.0).generate(300).unwrap();
        let mirrored: Vec<Point> = helix
            .points()
            .iter()
            .map(|p| Point::new(p.x, -p.y, p.z))
            .collect();
        let mirrored = Curve::from_points(mirrored).unwrap();
        let e = shape_error(&mirrored, &helix, 200).unwrap();
        assert!(e.rms_mm > 1.0);
        assert!((e.rotation.matrix().determinant() - 1.0).abs() < 1e-9);
    }

    #[test]
    fn bent_copy_has_an_error_between_bounds() {
        // A 100 mm line against a quarter circle of the same length: the aligned
        // RMS must be positive and well under the arc's sagitta-scale offsets.
        let line = Preset::Line(LineParams { length_mm: 100.0 })
            .generate(101)
            .unwrap();
        let arc = Preset::Arc(ArcParams {
            radius_mm: 100.0 / std::f64::consts::FRAC_PI_2,
            angle_deg: 90.0,
        })
        .generate(101)
        .unwrap();
        let e = shape_error(&arc, &line, 101).unwrap();
        assert!(e.rms_mm > 1.0 && e.rms_mm < 20.0, "{}", e.rms_mm);
        assert!((e.percent_of_length - e.rms_mm).abs() < 1e-9);
    }
}
