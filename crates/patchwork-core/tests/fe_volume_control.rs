//! Volume control traces a neo-Hookean tube through its pressure maximum.
//!
//! Membrane theory (DESIGN.md): the closed-end neo-Hookean tube's normalised
//! pressure p = P R0/(μ t0) peaks at p = 0.749868 with hoop stretch
//! λ₁ = 1.576875. Pressure control cannot pass that point; volume control
//! (pressure as a Lagrange multiplier) can. Tolerance (issue): 1 %.

use patchwork_core::design::{Balloon, Design};
use patchwork_core::fe::centreline::rings;
use patchwork_core::fe::mesh::MeshSpec;
use patchwork_core::fe::model::Model;
use patchwork_core::fe::newton::NewtonOptions;
use patchwork_core::fe::section::CutElements;
use patchwork_core::fe::volume_control::VolumeSolver;
use patchwork_core::fe::{SimulateOptions, simulate};
use patchwork_core::material::{Law, Material};

const R0: f64 = 3.18;
const T0: f64 = 0.183;
const MU: f64 = 0.317;

#[test]
fn neo_hookean_pressure_maximum_by_volume_control() {
    let to_p = |pressure_mpa: f64| pressure_mpa * R0 / (MU * T0);
    let design = Design {
        balloon: Balloon {
            length_mm: 25.0 * R0,
            radius_mm: R0,
            wall_mm: T0,
            material: Material::incompressible(Law::NeoHookean { mu_mpa: MU }),
        },
        pressure_kpa: 0.5 * MU * T0 / R0 * 1e3,
        ..Design::reference(vec![])
    };
    let options = SimulateOptions {
        mesh: MeshSpec {
            element_mm: 1.0,
            around: Some(40),
            straight_mm: None,
        },
        rings: 25,
        ..SimulateOptions::default()
    };
    let start = simulate(&design, &options).expect("pressure-controlled start at p = 0.5");
    let model = Model::new(&design, start.mesh.clone(), CutElements::default());
    let solver = VolumeSolver::new(&model).unwrap();
    let mut x = start.positions.clone();
    let mut pressure = design.pressure_mpa();
    let v0 = model.volume(&x);
    let mut history: Vec<(f64, f64)> = Vec::new();
    let newton = NewtonOptions {
        tolerance: 1e-8,
        ..NewtonOptions::default()
    };
    for k in 1..=60 {
        let target = v0 * (1.0 + 0.025 * k as f64);
        let mut trial = x.clone();
        let mut trial_pressure = pressure;
        if let Err(e) = solver.solve(
            &model,
            &model.sections,
            &mut trial,
            &mut trial_pressure,
            target,
            &newton,
        ) {
            // Past the peak the uniform state can give way to a bulge; the trace
            // may stop there, but only once the maximum has been passed.
            let passed =
                history.len() >= 3 && history[history.len() - 1].1 < history[history.len() - 3].1;
            assert!(passed, "volume step {k} failed before the peak: {e}");
            println!("stopped at volume step {k}: {e}");
            break;
        }
        (x, pressure) = (trial, trial_pressure);
        let mid = rings(&model.mesh, &x, 25)[12].radius / R0;
        history.push((mid, to_p(pressure)));
        if mid > 1.9 {
            break;
        }
    }
    let (peak_index, &(hoop_at_peak, peak)) = history
        .iter()
        .enumerate()
        .max_by(|a, b| a.1.1.total_cmp(&b.1.1))
        .unwrap();
    // Refine the peak by a parabola through the three samples around it.
    let (hoop, p) = if peak_index > 0 && peak_index + 1 < history.len() {
        let (x0, y0) = history[peak_index - 1];
        let (x1, y1) = history[peak_index];
        let (x2, y2) = history[peak_index + 1];
        let denom = (x0 - x1) * (x0 - x2) * (x1 - x2);
        let a = (x2 * (y1 - y0) + x1 * (y0 - y2) + x0 * (y2 - y1)) / denom;
        let b = (x2 * x2 * (y0 - y1) + x1 * x1 * (y2 - y0) + x0 * x0 * (y1 - y2)) / denom;
        let xv = -b / (2.0 * a);
        (xv, y1 + a * (xv - x1) * (xv - x1))
    } else {
        (hoop_at_peak, peak)
    };
    println!(
        "pressure maximum p = {p:.6} at λ₁ = {hoop:.6} (theory 0.749868 at 1.576875); samples {history:?}"
    );
    assert!(
        history.last().unwrap().1 < p,
        "the trace must pass beyond the peak"
    );
    assert!((p - 0.749868).abs() / 0.749868 < 0.01, "peak pressure {p}");
    assert!(
        (hoop - 1.576875).abs() / 1.576875 < 0.01,
        "hoop stretch at the peak {hoop}"
    );
}
