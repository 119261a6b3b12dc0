//! The assembled model's gradient and Hessian against central finite
//! differences of its total potential, on a patched tube whose oblique patch
//! cuts elements (laminate and area-average sections both), in an inflated
//! state disturbed by a random (seeded) displacement.
//!
//! Tolerance: directional derivatives within 1e-6 relative (central
//! differences with step 1e-6 mm carry an O(h²) error ~1e-10 and rounding
//! ~1e-9 relative to the potential's size).

use patchwork_core::cmaes::rng::SeededRng;
use patchwork_core::design::{Balloon, Design, Patch};
use patchwork_core::fe::model::Model;
use patchwork_core::fe::section::CutElements;
use patchwork_core::fe::{SimulateOptions, simulate};

fn design() -> Design {
    Design {
        balloon: Balloon {
            length_mm: 30.0,
            ..Balloon::default()
        },
        ..Design::reference(vec![
            Patch {
                x_mm: 3.0,
                y_mm: 14.0,
                h_mm: 16.0,
                w_mm: 3.3,
                theta_deg: 30.0,
            },
            // A corner over another patch: overlaps and a blended section.
            Patch {
                x_mm: 6.0,
                y_mm: 22.0,
                h_mm: 5.0,
                w_mm: 5.0,
                theta_deg: -10.0,
            },
        ])
    }
}

/// K v from the lower-triangle values in pattern order.
fn hessian_times(model: &Model, values: &[f64], v: &[f64]) -> Vec<f64> {
    let mut out = vec![0.0; v.len()];
    for (pair, value) in model.pattern().iter().zip(values) {
        let (r, c) = (pair.row, pair.col);
        out[r] += value * v[c];
        if r != c {
            out[c] += value * v[r];
        }
    }
    out
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

fn norm(a: &[f64]) -> f64 {
    dot(a, a).sqrt()
}

#[test]
fn gradient_and_hessian_match_finite_differences() {
    let design = design();
    for rule in [CutElements::Laminate, CutElements::AreaAverage] {
        let options = SimulateOptions {
            cut_elements: rule,
            ..SimulateOptions::default()
        };
        let sim = simulate(&design, &options).expect("solve");
        let model = Model::new(&design, sim.mesh.clone(), rule);
        let laminates = model
            .sections
            .iter()
            .filter(|s| s.laminate.is_some())
            .count();
        match rule {
            CutElements::Laminate => assert!(laminates > 20, "{laminates} cut elements"),
            CutElements::AreaAverage => assert_eq!(laminates, 0),
        }
        let mut rng = SeededRng::new(7);
        let mut u = model.unknowns(&sim.positions);
        for ui in &mut u {
            *ui += 0.05 * rng.normal();
        }
        let n = model.dof_count;
        let (mut gradient, mut values) = (vec![0.0; n], Vec::new());
        model
            .assemble(
                &model.positions(&u),
                &model.sections,
                0.0,
                &mut gradient,
                &mut values,
            )
            .expect("admissible state");
        let h = 1e-6;
        for trial in 0..3 {
            let v: Vec<f64> = (0..n).map(|_| rng.normal()).collect();
            let v_norm = norm(&v);
            let v: Vec<f64> = v.iter().map(|x| x / v_norm).collect();
            let shifted = |sign: f64| -> Vec<f64> {
                u.iter()
                    .zip(&v)
                    .map(|(ui, vi)| ui + sign * h * vi)
                    .collect()
            };
            let (plus, minus) = (shifted(1.0), shifted(-1.0));
            let potential = |w: &[f64]| model.potential(&model.positions(w), &model.sections);
            let slope = (potential(&plus) - potential(&minus)) / (2.0 * h);
            let exact = dot(&gradient, &v);
            assert!(
                (slope - exact).abs() < 1e-6 * norm(&gradient),
                "{rule:?} trial {trial}: slope {slope} vs {exact}"
            );
            let gradient_at = |w: &[f64]| {
                let (mut g, mut vals) = (vec![0.0; n], Vec::new());
                model
                    .assemble(&model.positions(w), &model.sections, 0.0, &mut g, &mut vals)
                    .expect("admissible");
                g
            };
            let (gp, gm) = (gradient_at(&plus), gradient_at(&minus));
            let fd: Vec<f64> = gp
                .iter()
                .zip(&gm)
                .map(|(p, m)| (p - m) / (2.0 * h))
                .collect();
            let kv = hessian_times(&model, &values, &v);
            let error: Vec<f64> = fd.iter().zip(&kv).map(|(a, b)| a - b).collect();
            assert!(
                norm(&error) < 1e-6 * norm(&kv),
                "{rule:?} trial {trial}: |FD − Kv| = {:e}, |Kv| = {:e}",
                norm(&error),
                norm(&kv)
            );
        }
    }
}
