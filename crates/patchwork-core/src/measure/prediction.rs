//! What a built balloon is compared with: the design, its predicted
//! inflated centreline and the target, as design.json holds them.

use serde::Deserialize;

use super::error::CompareError;
use crate::curve::{Curve, Point, interpolate};
use crate::design::Design;

/// The fields of design.json a comparison reads (others are ignored, so
/// a report of any version with these fields will do).
#[derive(Deserialize)]
struct DesignFile {
    design: Design,
    centreline_mm: Vec<[f64; 3]>,
    #[serde(default)]
    centreline_radius_mm: Vec<f64>,
    #[serde(default)]
    cap_height_mm: Option<f64>,
    #[serde(default)]
    target_mm: Vec<[f64; 3]>,
}

/// A design and what it predicts.
#[derive(Debug, Clone, PartialEq)]
pub struct Prediction {
    pub design: Design,
    /// The predicted inflated centreline, base to tip: ring centres at equal
    /// steps of the uninflated length (design.json's `centreline_mm`).
    pub centreline: Curve,
    /// Arc length along the predicted centreline at each ring (mm).
    ring_s: Vec<f64>,
    /// The uninflated axial position of each ring (mm).
    ring_y: Vec<f64>,
    /// The target as the user gave it, when known.
    pub target: Option<Curve>,
    /// The fitted radius of each ring (mm); empty when not known.
    pub radius: Vec<f64>,
    /// How far the cap's pole lies past the last ring (mm), when known.
    pub cap_height: Option<f64>,
}

impl Prediction {
    /// `centreline` as design.json's `centreline_mm`: ring centres at equal
    /// steps of the design's uninflated length, base to tip.
    pub fn new(
        design: Design,
        centreline: &[Point],
        target: Option<Curve>,
    ) -> Result<Prediction, CompareError> {
        let invalid = |why: String| CompareError::Design(format!("centreline_mm: {why}"));
        if centreline.len() < Curve::MIN_POINTS {
            return Err(invalid(format!(
                "{} points, at least {} are needed",
                centreline.len(),
                Curve::MIN_POINTS
            )));
        }
        let curve = Curve::from_points(centreline.to_vec()).map_err(|e| invalid(e.to_string()))?;
        let last = (centreline.len() - 1) as f64;
        let length = design.balloon.length_mm;
        let ring_y = (0..centreline.len())
            .map(|i| length * i as f64 / last)
            .collect();
        let mut ring_s = vec![0.0];
        for pair in centreline.windows(2) {
            ring_s.push(ring_s[ring_s.len() - 1] + (pair[1] - pair[0]).norm());
        }
        Ok(Prediction {
            design,
            centreline: curve,
            ring_s,
            ring_y,
            target,
            radius: Vec::new(),
            cap_height: None,
        })
    }

    /// Reads design.json (as `patchwork design` writes it and the API's
    /// result serves it).
    pub fn from_design_json(text: &str) -> Result<Prediction, CompareError> {
        let value: serde_json::Value =
            serde_json::from_str(text).map_err(|e| CompareError::Design(e.to_string()))?;
        if value.get("patches").is_some() && value.get("centreline_mm").is_none() {
            return Err(CompareError::Design(
                "a design without its prediction: give the design.json that `patchwork design` \
                 writes (its `design` and `centreline_mm`)"
                    .into(),
            ));
        }
        let file: DesignFile =
            serde_json::from_value(value).map_err(|e| CompareError::Design(e.to_string()))?;
        file.design
            .validate()
            .map_err(|e| CompareError::Design(format!("design: {e}")))?;
        let points = |raw: &[[f64; 3]]| -> Vec<Point> {
            raw.iter().map(|p| Point::new(p[0], p[1], p[2])).collect()
        };
        let target = match file.target_mm.is_empty() {
            true => None,
            false => Some(
                Curve::from_points(points(&file.target_mm))
                    .map_err(|e| CompareError::Design(format!("target_mm: {e}")))?,
            ),
        };
        let mut prediction = Prediction::new(file.design, &points(&file.centreline_mm), target)?;
        prediction.cap_height = file.cap_height_mm.filter(|h| h.is_finite() && *h >= 0.0);
        Ok(
            match file.centreline_radius_mm.len() == file.centreline_mm.len() {
                true => Prediction {
                    radius: file.centreline_radius_mm,
                    ..prediction
                },
                false => prediction,
            },
        )
    }

    /// The same prediction with the rings' radii (one per centreline point)
    /// and the cap's height.
    pub fn with_radius(self, radius: Vec<f64>, cap_height: Option<f64>) -> Prediction {
        Prediction {
            radius,
            cap_height,
            ..self
        }
    }

    /// The same prediction measured against `target` instead.
    pub fn with_target(self, target: Curve) -> Prediction {
        Prediction {
            target: Some(target),
            ..self
        }
    }

    /// Arc length along the predicted centreline (mm) where the uninflated
    /// balloon's axial position is `y_mm`.
    pub fn arc_length_at(&self, y_mm: f64) -> f64 {
        interpolate(&self.ring_y, &self.ring_s, y_mm)
    }

    /// The rings' radii at their fractions of the inflated length; none
    /// when design.json did not keep them.
    pub fn radius_profile(&self) -> Option<(Vec<f64>, Vec<f64>)> {
        if self.radius.len() != self.ring_s.len() {
            return None;
        }
        let fractions = self.ring_s.iter().map(|s| s / self.length()).collect();
        Some((fractions, self.radius.clone()))
    }

    /// The predicted inflated length (mm).
    pub fn length(&self) -> f64 {
        self.ring_s[self.ring_s.len() - 1]
    }
}
