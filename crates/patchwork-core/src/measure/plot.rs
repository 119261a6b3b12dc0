//! `compare.svg`: κ and τ along the length, measured against predicted
//! (and the target's, when known), with every patch's stretch marked.

use crate::chart::{self, Axis, COLOURS, Mark, Panel, Series};

use super::Comparison;

/// The two panels (curvature, torsion) of a comparison.
pub fn comparison_svg(comparison: &Comparison) -> String {
    let profiles = &comparison.profiles;
    let along = |values: &[f64]| -> Vec<(f64, f64)> {
        profiles
            .fraction
            .iter()
            .zip(values)
            .map(|(f, v)| (100.0 * f, *v))
            .collect()
    };
    let panel = |title: &str, label: &str, measured: &[f64], predicted: &[f64], target: &[f64]| {
        let values = measured.iter().chain(predicted).chain(target).copied();
        let y = Axis::linear(label, values.chain([0.0, 1e-3]));
        let mut series = vec![
            Series {
                name: Some("measured".into()),
                colour: COLOURS[1],
                mark: Mark::Line,
                points: along(measured),
            },
            Series {
                name: Some("predicted".into()),
                colour: COLOURS[0],
                mark: Mark::Line,
                points: along(predicted),
            },
        ];
        if !target.is_empty() {
            series.push(Series {
                name: Some("target".into()),
                colour: "#555555",
                mark: Mark::Dashed,
                points: along(target),
            });
        }
        series.extend(patch_marks(comparison, y.value_at(0.04)));
        Panel {
            title: title.into(),
            x: Axis::linear("position along the balloon (% of its length)", [0.0, 100.0]),
            y,
            series,
        }
    };
    chart::svg(&[
        panel(
            "Curvature",
            "curvature κ (1/mm)",
            &profiles.measured_curvature_per_mm,
            &profiles.predicted_curvature_per_mm,
            &profiles.target_curvature_per_mm,
        ),
        panel(
            "Torsion",
            "torsion τ (1/mm)",
            &profiles.measured_torsion_per_mm,
            &profiles.predicted_torsion_per_mm,
            &profiles.target_torsion_per_mm,
        ),
    ])
}

/// Each patch's stretch as a bar at height `y` (the most divergent one in
/// its own colour); one legend entry for them all.
fn patch_marks(comparison: &Comparison, y: f64) -> Vec<Series> {
    comparison
        .patches
        .iter()
        .enumerate()
        .map(|(i, region)| {
            let worst = comparison.most_divergent_patch == Some(region.patch);
            Series {
                name: match (i, worst) {
                    (_, true) => Some(format!("P{}: diverges most", region.patch)),
                    (0, false) => Some("patches' stretches".into()),
                    _ => None,
                },
                colour: if worst { COLOURS[3] } else { COLOURS[8] },
                mark: Mark::Line,
                points: vec![
                    (100.0 * region.from_fraction, y),
                    (100.0 * region.to_fraction, y),
                ],
            }
        })
        .collect()
}
