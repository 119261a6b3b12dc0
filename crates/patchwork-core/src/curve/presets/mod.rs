//! Preset target curves with parameters, and the three reference curves from the
//! authors' code (MIT licence, `data/curves/LICENSE`).
//!
//! Analytic presets are sampled uniformly in arc length, every sample lying exactly
//! on the curve. Parameter names are the JSON names used by the CLI
//! (`patchwork preset helix radius_mm=20`) and the API (`{"preset", "params"}`).

mod hilbert;
mod sampling;

use std::f64::consts::TAU;

use serde::{Deserialize, Serialize};

use super::{Curve, CurveError, Point, Units, read_text};
use hilbert::hilbert;
pub use hilbert::hilbert_length;
use sampling::{by_arc_length, finite, positive};

/// Number of samples when the caller does not choose.
pub const DEFAULT_POINTS: usize = 400;

/// A curve family and its parameters.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "preset", content = "params", rename_all = "snake_case")]
pub enum Preset {
    /// Circular helix about z: radius, pitch (rise per turn), number of turns.
    Helix(HelixParams),
    /// First-order 3D Hilbert curve on a cube (7 edges) with circular fillets.
    Hilbert(HilbertParams),
    /// Closed contour on a hyperbolic paraboloid: z = h cos 2θ on a cylinder of
    /// radius R (the authors' "pancake" is R = 106.8 mm, h = 80 mm).
    Saddle(SaddleParams),
    /// Trefoil knot (sin t + 2 sin 2t, cos t − 2 cos 2t, −sin 3t)·scale.
    Trefoil(TrefoilParams),
    /// Planar circular arc in the xy plane.
    Arc(ArcParams),
    /// Straight line along x.
    Line(LineParams),
    /// A helix whose radius and pitch change linearly along it (a conical
    /// spiral when the pitch is small).
    Spiral(SpiralParams),
    /// Planar S of two equal arcs, with an optional kink at the joint.
    SCurve(SCurveParams),
    /// Planar hook: a straight shank and an arc of the given opening.
    Hook(HookParams),
    /// Grasp a cylinder: a straight lead, then a helix around the cylinder.
    Grasp(GraspParams),
    /// One of the authors' published target curves.
    Reference(ReferenceParams),
}

macro_rules! params {
    ($(#[$doc:meta])* $name:ident { $($field:ident : $default:expr),* $(,)? }) => {
        $(#[$doc])*
        #[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
        #[serde(default, deny_unknown_fields)]
        pub struct $name { $(pub $field: f64),* }
        impl Default for $name {
            fn default() -> Self { $name { $($field: $default),* } }
        }
    };
}

params!(HelixParams {
    radius_mm: 20.0,
    pitch_mm: 60.0,
    turns: 4.0
});
params!(HilbertParams {
    edge_mm: 144.0,
    corner_radius_mm: 47.0
});
params!(SaddleParams {
    radius_mm: 106.8,
    height_mm: 80.0
});
params!(TrefoilParams { scale_mm: 40.0 });
params!(ArcParams {
    radius_mm: 100.0,
    angle_deg: 180.0
});
params!(LineParams { length_mm: 600.0 });
params!(SpiralParams {
    start_radius_mm: 25.0,
    end_radius_mm: 60.0,
    start_pitch_mm: 20.0,
    end_pitch_mm: 20.0,
    turns: 1.5
});
params!(SCurveParams {
    radius_mm: 60.0,
    angle_deg: 90.0,
    kink_deg: 0.0
});
params!(HookParams {
    shank_mm: 120.0,
    opening_mm: 60.0,
    angle_deg: 200.0
});
params!(GraspParams {
    diameter_mm: 40.0,
    turns: 1.5,
    pitch_mm: 40.0,
    lead_mm: 60.0,
    tube_radius_mm: 16.5
});

mod applications;

/// Which published reference curve.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ReferenceCurve {
    /// First-order 3D Hilbert curve with rounded corners, ≈ 899 mm.
    Hilbert,
    /// Hyperbolic-paraboloid contour, ≈ 953 mm.
    Pancake,
    /// Spring-like helix, ≈ 893 mm.
    Spring,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ReferenceParams {
    pub name: ReferenceCurve,
}

impl ReferenceCurve {
    pub const ALL: [ReferenceCurve; 3] = [
        ReferenceCurve::Hilbert,
        ReferenceCurve::Pancake,
        ReferenceCurve::Spring,
    ];

    fn csv(self) -> &'static str {
        match self {
            ReferenceCurve::Hilbert => include_str!("../../../data/curves/hilbert_curve.csv"),
            ReferenceCurve::Pancake => include_str!("../../../data/curves/pancake_curve.csv"),
            ReferenceCurve::Spring => include_str!("../../../data/curves/spring_like_curve.csv"),
        }
    }

    /// The curve exactly as published (mm).
    pub fn curve(self) -> Curve {
        read_text(self.csv(), Units::Mm).expect("bundled reference curve is valid")
    }

    pub fn name(self) -> &'static str {
        match self {
            ReferenceCurve::Hilbert => "hilbert",
            ReferenceCurve::Pancake => "pancake",
            ReferenceCurve::Spring => "spring",
        }
    }
}

impl Preset {
    /// The preset names as written on the command line and in JSON.
    pub const NAMES: [&'static str; 11] = [
        "helix",
        "hilbert",
        "saddle",
        "trefoil",
        "arc",
        "line",
        "spiral",
        "s_curve",
        "hook",
        "grasp",
        "reference",
    ];

    pub fn helix(radius_mm: f64, pitch_mm: f64, turns: f64) -> Preset {
        Preset::Helix(HelixParams {
            radius_mm,
            pitch_mm,
            turns,
        })
    }

    /// Builds a preset from its name and a JSON object of parameters (missing
    /// ones take their defaults; unknown ones are an error naming them).
    pub fn from_name(name: &str, params: serde_json::Value) -> Result<Preset, String> {
        let tagged = serde_json::json!({ "preset": name, "params": params });
        serde_json::from_value(tagged).map_err(|e| {
            if Self::NAMES.contains(&name) {
                format!("preset {name}: {e}")
            } else {
                format!(
                    "unknown preset {name:?}: choose one of {}",
                    Self::NAMES.join(", ")
                )
            }
        })
    }

    /// Samples the curve. `points = None` gives [`DEFAULT_POINTS`] samples for
    /// analytic presets and the published samples for reference curves.
    pub fn curve(&self, points: Option<usize>) -> Result<Curve, CurveError> {
        if let Preset::Reference(ReferenceParams { name }) = self {
            let curve = name.curve();
            return match points {
                Some(n) => curve.resample(n),
                None => Ok(curve),
            };
        }
        self.generate(points.unwrap_or(DEFAULT_POINTS))
    }

    /// Samples the curve at `n` points equally spaced in arc length.
    pub fn generate(&self, n: usize) -> Result<Curve, CurveError> {
        if !(Curve::MIN_POINTS..=Curve::MAX_POINTS).contains(&n) {
            return Err(CurveError::ResampleCount {
                requested: n,
                min: Curve::MIN_POINTS,
                max: Curve::MAX_POINTS,
            });
        }
        match self {
            Preset::Helix(p) => {
                positive("radius_mm", p.radius_mm)?;
                finite("pitch_mm", p.pitch_mm)?;
                positive("turns", p.turns)?;
                let (a, b) = (p.radius_mm, p.pitch_mm / TAU);
                let end = TAU * p.turns;
                // Uniform in t is uniform in arc length for a helix.
                let points = (0..n)
                    .map(|i| end * i as f64 / (n - 1) as f64)
                    .map(|t| Point::new(a * t.cos(), a * t.sin(), b * t))
                    .collect();
                Curve::from_points(points)
            }
            Preset::Hilbert(p) => {
                positive("edge_mm", p.edge_mm)?;
                positive("corner_radius_mm", p.corner_radius_mm)?;
                if p.corner_radius_mm > p.edge_mm / 2.0 {
                    return Err(CurveError::InvalidParameter {
                        name: "corner_radius_mm",
                        value: p.corner_radius_mm,
                        reason: "must be at most half of edge_mm",
                    });
                }
                hilbert(p.edge_mm, p.corner_radius_mm, n)
            }
            Preset::Saddle(p) => {
                positive("radius_mm", p.radius_mm)?;
                finite("height_mm", p.height_mm)?;
                let (r, h) = (p.radius_mm, p.height_mm);
                by_arc_length(
                    |t| Point::new(r * t.cos(), r * t.sin(), -h * (2.0 * t).cos()),
                    TAU,
                    n,
                )
            }
            Preset::Trefoil(p) => {
                positive("scale_mm", p.scale_mm)?;
                let k = p.scale_mm;
                by_arc_length(
                    |t| {
                        k * Point::new(
                            t.sin() + 2.0 * (2.0 * t).sin(),
                            t.cos() - 2.0 * (2.0 * t).cos(),
                            -(3.0 * t).sin(),
                        )
                    },
                    TAU,
                    n,
                )
            }
            Preset::Arc(p) => {
                positive("radius_mm", p.radius_mm)?;
                positive("angle_deg", p.angle_deg)?;
                if p.angle_deg >= 360.0 {
                    return Err(CurveError::InvalidParameter {
                        name: "angle_deg",
                        value: p.angle_deg,
                        reason: "must be below 360",
                    });
                }
                let (r, end) = (p.radius_mm, p.angle_deg.to_radians());
                let points = (0..n)
                    .map(|i| end * i as f64 / (n - 1) as f64)
                    .map(|t| Point::new(r * t.sin(), r * (1.0 - t.cos()), 0.0))
                    .collect();
                Curve::from_points(points)
            }
            Preset::Line(p) => {
                positive("length_mm", p.length_mm)?;
                let points = (0..n)
                    .map(|i| Point::new(p.length_mm * i as f64 / (n - 1) as f64, 0.0, 0.0))
                    .collect();
                Curve::from_points(points)
            }
            Preset::Spiral(p) => applications::spiral(p, n),
            Preset::SCurve(p) => applications::s_curve(p, n),
            Preset::Hook(p) => applications::hook(p, n),
            Preset::Grasp(p) => applications::grasp(p, n),
            Preset::Reference(ReferenceParams { name }) => name.curve().resample(n),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reference_curves_load_with_published_lengths() {
        let lengths = [
            (ReferenceCurve::Hilbert, 899.0),
            (ReferenceCurve::Pancake, 953.0),
            (ReferenceCurve::Spring, 893.0),
        ];
        for (name, length) in lengths {
            let c = name.curve();
            assert!(
                (c.length() - length).abs() < 1.0,
                "{:?} {}",
                name,
                c.length()
            );
        }
    }

    #[test]
    fn hilbert_preset_has_exact_length_and_continuous_samples() {
        let c = Preset::Hilbert(HilbertParams::default())
            .generate(2000)
            .unwrap();
        let expected = hilbert_length(144.0, 47.0);
        // Chord length falls short of arc length by O(h²κ²) on the fillets.
        assert!(
            (c.length() - expected).abs() / expected < 1e-4,
            "{} vs {expected}",
            c.length()
        );
        let spacing = expected / 1999.0;
        for w in c.points().windows(2) {
            assert!((w[1] - w[0]).norm() < spacing * 1.0001);
        }
    }

    #[test]
    fn analytic_presets_are_uniform_in_arc_length() {
        for preset in [
            Preset::Saddle(SaddleParams::default()),
            Preset::Trefoil(TrefoilParams::default()),
        ] {
            let c = preset.generate(500).unwrap();
            let steps: Vec<f64> = c.arc_length().windows(2).map(|w| w[1] - w[0]).collect();
            let mean = c.length() / 499.0;
            assert!(
                steps.iter().all(|d| (d - mean).abs() / mean < 1e-3),
                "{preset:?}"
            );
        }
    }

    #[test]
    fn parameters_are_validated_by_name() {
        let err = Preset::helix(-1.0, 10.0, 2.0).generate(100).unwrap_err();
        assert!(err.to_string().contains("radius_mm"));
        // Every parameter is bounded: a 200 m helix radius, a 0.0001 mm one
        // and a pitch of 1 km are refused, their limits included.
        for (radius, pitch) in [(2e5, 10.0), (1e-4, 10.0), (20.0, -1e6)] {
            let err = Preset::helix(radius, pitch, 2.0).generate(100).unwrap_err();
            assert!(err.to_string().contains("100000"), "{err}");
        }
        assert!(Preset::helix(1e5, -1e5, 1e-3).generate(100).is_ok());
        let err = Preset::from_name("helix", serde_json::json!({"radius": 3})).unwrap_err();
        assert!(err.contains("radius"), "{err}");
        let err = Preset::from_name("lissajous", serde_json::json!({})).unwrap_err();
        assert!(err.contains("unknown preset"), "{err}");
        let ok = Preset::from_name("helix", serde_json::json!({"turns": 2})).unwrap();
        assert_eq!(ok, Preset::helix(20.0, 60.0, 2.0));
    }
}
