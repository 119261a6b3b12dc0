//! The rod model (`patchwork_core::rod`) against the FE model it is fitted
//! to: its table's one-patch fits, and designs of several patches that no
//! fit saw (docs/studies.md, "A rod model for the search", measures it on
//! 40 designs).

use patchwork_core::curve::{Preset, ReferenceCurve, shape_error};
use patchwork_core::design::Design;
use patchwork_core::fe::{SimulateOptions, simulate};
use patchwork_core::inverse::{Fidelity, VariableBounds};
use patchwork_core::ksa::{KsaParams, ksa};
use patchwork_core::rod::RodTable;

/// The `draft` preset's verification model, which the search's table is
/// solved on.
fn model() -> SimulateOptions {
    let radius = Design::reference(vec![]).balloon.radius_mm;
    SimulateOptions {
        mesh: Fidelity::Draft.tuning(radius).verify_mesh,
        ..SimulateOptions::default()
    }
}

/// The KSA seed of `name`'s curve on the reference balloon, the balloon
/// a third of the curve's length (the inflated stretch is about 3).
fn seed(name: &str) -> Design {
    let curve = match name {
        "hilbert" => ReferenceCurve::Hilbert.curve(),
        preset => (Preset::from_name(preset, serde_json::json!({})).unwrap())
            .curve(None)
            .unwrap(),
    };
    let l0 = curve.length() / 3.0;
    let params = KsaParams {
        l0_mm: l0,
        ..KsaParams::default()
    };
    let mut design = Design::reference(ksa(&curve, &params).unwrap().patches);
    design.balloon.length_mm = l0;
    design
}

/// One table for the whole test: every fit within 1.5 mm (RMS over the
/// balloon's 201 rings) up to 70°; the rod of three KSA seeds within 3.5 %
/// of the FE centreline's length (shape error; the study's 40 designs:
/// median 1.8 %, worst 3.1 %), each in under a millisecond or a hundredth
/// of the FE solve's time.
#[test]
fn the_rod_follows_fe_on_designs_its_table_never_saw() {
    let options = model();
    let base = Design::reference(vec![]);
    let bounds = VariableBounds::default();
    let table = RodTable::compute(&base, &bounds, &options, 2, &|| false).unwrap();
    assert!(table.is_complete(&bounds));
    let mut k = 0;
    for h in &table.lengths_mm {
        for w in &table.widths_mm {
            for theta in &table.angles_deg {
                let fit = table.fit_mm[k];
                k += 1;
                if *theta <= 70.0 {
                    assert!(fit < 1.5, "H {h} W {w} Θ {theta}: fit {fit:.2} mm");
                }
            }
        }
    }
    for name in ["hook", "hilbert", "spiral"] {
        let design = seed(name);
        let fe = simulate(&design, &options).unwrap();
        let started = std::time::Instant::now();
        let rod = table.centreline(&design).unwrap();
        let rod_s = started.elapsed().as_secs_f64();
        let error = shape_error(&rod, &fe.centreline, 200).unwrap();
        eprintln!("{name}: rod {:.2} % from FE", error.percent_of_length);
        assert!(
            error.percent_of_length < 3.5,
            "{name}: rod {:.2} % from FE",
            error.percent_of_length
        );
        assert!(rod_s < 1e-3 || rod_s < fe.elapsed.as_secs_f64() / 100.0);
    }
}

/// A table whose `stop` answers true part way solves no further balloon
/// and is not complete, so no search uses it and no store keeps it.
#[test]
fn a_stopped_table_is_incomplete() {
    let calls = std::sync::atomic::AtomicUsize::new(0);
    let stop = || calls.fetch_add(1, std::sync::atomic::Ordering::Relaxed) >= 3;
    let bounds = VariableBounds::default();
    let base = Design::reference(vec![]);
    let table = RodTable::compute(&base, &bounds, &model(), 1, &stop).unwrap();
    assert_eq!(table.entries.len(), 3);
    assert!(!table.is_complete(&bounds));
}

/// A rod table mirrors a patch at −Θ: the same bend, its side turned the
/// other way round the tube, so the centreline is the mirror image through
/// the plane of the tube's axis and x̂.
#[test]
fn a_patch_at_minus_theta_is_the_mirror_image() {
    let table = RodTable {
        bare: patchwork_core::rod::BareTube::uniform(3.5),
        lengths_mm: vec![10.0, 30.0],
        widths_mm: vec![1.0, 3.0],
        angles_deg: vec![0.0, 45.0],
        entries: (0..8)
            .map(|k| patchwork_core::rod::PatchRod {
                curvature: 0.02 + 0.01 * k as f64,
                twist: 0.1 * (k % 2) as f64,
                phase: -0.1 * (k % 2) as f64,
                stretch: -0.5,
            })
            .collect(),
        fit_mm: vec![0.0; 8],
    };
    let design = |theta_deg: f64| {
        let mut d = Design::reference(vec![patchwork_core::design::Patch {
            x_mm: 0.0,
            y_mm: 50.0,
            h_mm: 20.0,
            w_mm: 2.0,
            theta_deg,
        }]);
        d.balloon.length_mm = 100.0;
        d
    };
    let plus = table.centreline(&design(30.0)).unwrap();
    let minus = table.centreline(&design(-30.0)).unwrap();
    assert!(plus.points().last().unwrap().y.abs() > 1.0);
    for (p, m) in plus.points().iter().zip(minus.points()) {
        assert!((p.x - m.x).abs() < 1e-9 && (p.y + m.y).abs() < 1e-9 && (p.z - m.z).abs() < 1e-9);
    }
}
