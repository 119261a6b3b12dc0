//! The FE model of a bare closed-end tube of incompressible material against
//! membrane theory (DESIGN.md).
//!
//! The closed form is written here independently of the core: analytic ∂W/∂λᵢ
//! for each model, normalised by μ, and the two equilibrium equations
//!   hoop  p = W₁/(λ₁λ₂),   axial  λ₁W₁ = 2λ₂W₂,   p = P R₀/(μ t₀).
//!
//! Tolerance: mid-tube hoop and axial stretch within 0.2 % on rising
//! branches (the issue asked for 1 %; measured within 0.04 %). Mesh: 40 nodes
//! around, whose facets the model loads with P / cos(π/40)
//! (`fe::pressure::facet_load_factor`; loaded with P they fell 0.1–0.3 %
//! short), 1 mm axially, tube 25 radii long so the middle is far from both
//! ends.

use patchwork_core::design::{Balloon, Design};
use patchwork_core::fe::mesh::MeshSpec;
use patchwork_core::fe::{SimulateOptions, simulate};
use patchwork_core::material::{Compressibility, Law, Material};

const R0: f64 = 3.18;
const T0: f64 = 0.183;

/// dW/dI₁ / μ for the invariant models.
fn dw_di1(model: &Model, i1: f64) -> f64 {
    match model {
        Model::NeoHookean => 0.5,
        Model::Gent { jm } => 0.5 / (1.0 - (i1 - 3.0) / jm),
        Model::ArrudaBoyce { lambda_m } => {
            let c = [
                0.5,
                1.0 / 20.0,
                11.0 / 1050.0,
                19.0 / 7000.0,
                519.0 / 673750.0,
            ];
            (0..5)
                .map(|k| c[k] * (k + 1) as f64 * i1.powi(k as i32) / lambda_m.powi(2 * k as i32))
                .sum()
        }
    }
}

enum Model {
    NeoHookean,
    Gent { jm: f64 },
    ArrudaBoyce { lambda_m: f64 },
}

/// (W₁, W₂) = ∂W/∂λᵢ / μ with λ₃ = 1/(λ₁λ₂).
fn w12(model: &Model, l1: f64, l2: f64) -> (f64, f64) {
    let i1 = l1 * l1 + l2 * l2 + 1.0 / (l1 * l1 * l2 * l2);
    if let Model::Gent { jm } = model
        && i1 - 3.0 >= *jm
    {
        return (f64::NAN, f64::NAN);
    }
    let d = dw_di1(model, i1);
    let di1_dl1 = 2.0 * l1 - 2.0 / (l1.powi(3) * l2 * l2);
    let di1_dl2 = 2.0 * l2 - 2.0 / (l2.powi(3) * l1 * l1);
    (d * di1_dl1, d * di1_dl2)
}

fn axial(model: &Model, l1: f64) -> f64 {
    let g = |l2: f64| {
        let (w1, w2) = w12(model, l1, l2);
        l1 * w1 - 2.0 * l2 * w2
    };
    // Bracket by scanning upward, staying inside Gent's locking limit.
    let (mut lo, mut hi) = (0.5, 0.5);
    while g(hi).is_finite() && g(lo) * g(hi) > 0.0 {
        lo = hi;
        hi += 0.05;
    }
    assert!(g(lo) * g(hi) <= 0.0, "no axial root for λ₁ = {l1}");
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if g(mid) * g(lo) > 0.0 {
            lo = mid
        } else {
            hi = mid
        }
    }
    0.5 * (lo + hi)
}

fn pressure(model: &Model, l1: f64) -> f64 {
    let l2 = axial(model, l1);
    w12(model, l1, l2).0 / (l1 * l2)
}

#[test]
fn closed_form_reproduces_the_design_card() {
    let nh = Model::NeoHookean;
    for (l1, l2, p) in [
        (1.5, 1.138601, 0.744451),
        (2.0, 1.435500, 0.675493),
        (3.0, 2.124220, 0.469473),
    ] {
        assert!((axial(&nh, l1) - l2).abs() < 1e-6);
        assert!((pressure(&nh, l1) - p).abs() < 1e-6);
    }
    // Peak p = 0.749868 at λ₁ = 1.576875 (golden-section search on p(λ₁)).
    let (mut a, mut b) = (1.3, 2.0);
    for _ in 0..100 {
        let (c, d) = (b - 0.618 * (b - a), a + 0.618 * (b - a));
        if pressure(&nh, c) > pressure(&nh, d) {
            b = d
        } else {
            a = c
        }
    }
    assert!((0.5 * (a + b) - 1.576875).abs() < 1e-5);
    assert!((pressure(&nh, 0.5 * (a + b)) - 0.749868).abs() < 1e-6);
}

/// `mu` is the μ that normalises W in the closed form (the model's parameter).
fn check_fe(model: Model, material: Material, mu: f64, hoop: f64, label: &str) {
    let dp = pressure(&model, hoop + 1e-4) - pressure(&model, hoop - 1e-4);
    assert!(dp > 0.0, "{label}: λ₁ = {hoop} is not on a rising branch");
    let p = pressure(&model, hoop);
    let axial_expected = axial(&model, hoop);
    let pressure_kpa = p * mu * T0 / R0 * 1e3;
    let design = Design {
        balloon: Balloon {
            length_mm: 25.0 * R0,
            radius_mm: R0,
            wall_mm: T0,
            material,
        },
        pressure_kpa,
        ..Design::reference(vec![])
    };
    let options = SimulateOptions {
        mesh: MeshSpec {
            element_mm: 1.0,
            around: Some(40),
            straight_mm: None,
        },
        ..SimulateOptions::default()
    };
    let sim = simulate(&design, &options).unwrap_or_else(|e| panic!("{label}: {e}"));
    let (eh, ea) = (
        (sim.hoop_stretch_mid - hoop) / hoop,
        (sim.axial_stretch_mid - axial_expected) / axial_expected,
    );
    println!(
        "{label}: p = {p:.4} ({pressure_kpa:.2} kPa) hoop FE {:.5} theory {hoop:.5} ({:+.3} %), axial FE {:.5} theory {axial_expected:.5} ({:+.3} %)",
        sim.hoop_stretch_mid,
        100.0 * eh,
        sim.axial_stretch_mid,
        100.0 * ea
    );
    assert!(
        eh.abs() < 0.002 && ea.abs() < 0.002,
        "{label}: outside 0.2 %"
    );
    assert!(sim.stats.stable, "{label}: equilibrium not stable");
}

#[test]
fn neo_hookean_tube_before_the_pressure_peak() {
    check_fe(
        Model::NeoHookean,
        Material::incompressible(Law::NeoHookean { mu_mpa: 0.317 }),
        0.317,
        1.4,
        "neo-Hookean",
    );
}

#[test]
fn gent_tube_on_the_stiffening_branch() {
    check_fe(
        Model::Gent { jm: 20.0 },
        Material::incompressible(Law::Gent {
            mu_mpa: 0.317,
            jm: 20.0,
        }),
        0.317,
        3.4,
        "Gent",
    );
}

#[test]
fn arruda_boyce_tube_on_the_stiffening_branch() {
    check_fe(
        Model::ArrudaBoyce { lambda_m: 2.3 },
        Material::reference_balloon().with_compressibility(Compressibility::Incompressible),
        0.317,
        2.9,
        "Arruda–Boyce",
    );
}

/// The reference scene's materials taken incompressible, at 20 kPa: FE
/// mid-tube against the closed form at that pressure (found here by bisection
/// on the last rising branch). The compressible scene: fe_tube_compressible.rs.
#[test]
fn incompressible_reference_bare_tube_at_20_kpa() {
    let model = Model::ArrudaBoyce { lambda_m: 2.3 };
    let target = 20e-3 * R0 / (0.317 * T0);
    let mut crossing = None;
    let mut l1 = 1.0;
    while l1 < 6.0 {
        if pressure(&model, l1) < target && pressure(&model, l1 + 0.01) >= target {
            crossing = Some(l1);
        }
        l1 += 0.01;
    }
    let (mut lo, mut hi) = (crossing.unwrap(), crossing.unwrap() + 0.01);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if pressure(&model, mid) < target {
            lo = mid
        } else {
            hi = mid
        }
    }
    let hoop = 0.5 * (lo + hi);
    let axial_expected = axial(&model, hoop);
    let mut design = Design::reference(vec![]);
    design.balloon.material.compressibility = Compressibility::Incompressible;
    let options = SimulateOptions {
        mesh: MeshSpec {
            element_mm: 2.0,
            around: Some(40),
            straight_mm: None,
        },
        ..SimulateOptions::default()
    };
    let sim = simulate(&design, &options).unwrap();
    println!(
        "reference 20 kPa: hoop FE {:.5} theory {hoop:.5}, axial FE {:.5} theory {axial_expected:.5}",
        sim.hoop_stretch_mid, sim.axial_stretch_mid
    );
    assert!((sim.hoop_stretch_mid - hoop).abs() / hoop < 0.002);
    assert!((sim.axial_stretch_mid - axial_expected).abs() / axial_expected < 0.002);
    // The mesh a design is simulated on by default is as close.
    let default = simulate(
        &design,
        &SimulateOptions {
            mesh: MeshSpec::default_simulation(),
            ..SimulateOptions::default()
        },
    )
    .unwrap();
    println!(
        "default mesh: hoop FE {:.5}, axial FE {:.5}",
        default.hoop_stretch_mid, default.axial_stretch_mid
    );
    assert!((default.hoop_stretch_mid - hoop).abs() / hoop < 0.002);
    assert!((default.axial_stretch_mid - axial_expected).abs() / axial_expected < 0.002);
    // The core's own closed form (used as Newton's start) agrees with this one.
    assert!(
        (sim.tube_state.hoop - hoop).abs() < 1e-4
            && (sim.tube_state.axial - axial_expected).abs() < 1e-4
    );
}

/// A balloon whose mesh would not fit in memory is refused before a node is
/// built, naming the sizes (a 15 km target once asked for one; a design's
/// lengths are within 1 km, and a 100 m balloon already needs too many).
#[test]
fn a_mesh_too_large_to_solve_is_refused_before_it_is_built() {
    let mut design = patchwork_core::design::Design::reference(vec![]);
    design.balloon.length_mm = 100_000.0;
    let error = patchwork_core::fe::simulate(&design, &Default::default()).unwrap_err();
    let message = error.to_string();
    assert!(
        message.contains("100000 mm balloon") && message.contains("nodes"),
        "{message}"
    );
}
