//! Numerical stress suite: abusive designs and target curves. Every case
//! states its expected outcome — converged with finite numbers, a design
//! within a stated shape error, or a named typed error — and must meet it:
//! never a panic, a NaN or a hang (every solve runs under an iteration and a
//! time cap). The suite prints each case.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::{Duration, Instant};

use patchwork_core::CurveError;
use patchwork_core::cmaes::SeededRng;
use patchwork_core::curve::{Curve, Point, Preset};
use patchwork_core::design::{Balloon, Design, Patch};
use patchwork_core::fe::newton::NewtonOptions;
use patchwork_core::fe::{SimulateError, SimulateOptions, Simulation, simulate};
use patchwork_core::inverse::{Fidelity, Plan, TuningOverrides, UserSettings, design};
use patchwork_core::material::{Compressibility, Law, Material};

/// Refine solves of the abusive targets' designs: one Jacobian and some
/// trial steps for designs of up to 38 free variables.
const STRESS_REFINE: usize = 40;
/// Targets longer than this (mm) are designed without the refine: a long
/// helix's 1 mm solves take minutes each (docs/studies.md).
const NO_REFINE_BEYOND_MM: f64 = 1000.0;

/// Newton's time cap per solve; a case may take a few solves (continuation).
const SOLVE_CAP: Duration = Duration::from_secs(20);

fn options() -> SimulateOptions {
    SimulateOptions {
        newton: NewtonOptions {
            time_limit: SOLVE_CAP,
            ..NewtonOptions::default()
        },
        ..SimulateOptions::default()
    }
}

fn patch(x: f64, y: f64, h: f64, w: f64, theta: f64) -> Patch {
    Patch {
        x_mm: x,
        y_mm: y,
        h_mm: h,
        w_mm: w,
        theta_deg: theta,
    }
}

fn with_patches(patches: Vec<Patch>) -> Design {
    Design::reference(patches)
}

fn short(length_mm: f64, patches: Vec<Patch>) -> Design {
    Design {
        balloon: Balloon {
            length_mm,
            ..Balloon::default()
        },
        ..Design::reference(patches)
    }
}

/// A forward case's outcome and how long it took.
type Solved = (Result<Simulation, SimulateError>, Duration);

fn solve(design: &Design) -> Solved {
    let started = Instant::now();
    let outcome = simulate(design, &options());
    (outcome, started.elapsed())
}

/// What a forward case must end in.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Expect {
    Converges,
    /// Converges, or Newton fails with a typed error (designs far outside
    /// the fabrication bounds; within them every design must converge,
    /// `fe_robustness`).
    ConvergesOrFails,
    /// The design is refused before any solve, naming this field.
    Invalid(&'static str),
    /// The bare tube has no inflated state at the pressure.
    NoTubeState,
}

/// What a design case must end in.
#[derive(Debug, Clone, Copy, PartialEq)]
enum ExpectDesign {
    /// A valid design, verified within this shape error (%).
    Within(f64),
    /// The curve is refused: too few distinct points.
    TooFewPoints,
}

#[derive(Default)]
struct Tally {
    lines: Vec<String>,
    /// Cases of `Expect::ConvergesOrFails` that failed.
    failed: usize,
}

impl Tally {
    /// Runs one forward case and checks its outcome against `expect`.
    fn simulate(&mut self, name: &str, design: &Design, expect: Expect) {
        let (outcome, elapsed) = solve(design);
        self.check(name, expect, outcome, elapsed);
    }

    /// Runs forward cases on every core, then checks each outcome in order.
    fn simulate_all(&mut self, cases: Vec<(String, Design, Expect)>) {
        let next = AtomicUsize::new(0);
        let threads = patchwork_core::available_cores().min(cases.len());
        let mut solved: Vec<(usize, Solved)> = std::thread::scope(|scope| {
            let workers: Vec<_> = (0..threads)
                .map(|_| {
                    scope.spawn(|| {
                        let mut done = Vec::new();
                        loop {
                            let i = next.fetch_add(1, Ordering::Relaxed);
                            let Some((_, design, _)) = cases.get(i) else {
                                return done;
                            };
                            done.push((i, solve(design)));
                        }
                    })
                })
                .collect();
            workers
                .into_iter()
                .flat_map(|w| w.join().expect("a solve does not panic"))
                .collect()
        });
        solved.sort_by_key(|(i, _)| *i);
        for ((name, _, expect), (_, (outcome, elapsed))) in cases.into_iter().zip(solved) {
            self.check(&name, expect, outcome, elapsed);
        }
    }

    /// Checks one forward case's outcome against `expect`.
    fn check(
        &mut self,
        name: &str,
        expect: Expect,
        outcome: Result<Simulation, SimulateError>,
        elapsed: Duration,
    ) {
        assert!(elapsed < SOLVE_CAP * 8, "{name}: {elapsed:?} (hang?)");
        let ms = elapsed.as_secs_f64() * 1e3;
        let line = match (&outcome, expect) {
            (Ok(sim), Expect::Converges | Expect::ConvergesOrFails) => {
                let finite = sim
                    .positions
                    .iter()
                    .all(|p| p.iter().all(|v| v.is_finite()))
                    && sim
                        .curvature
                        .iter()
                        .chain(&sim.torsion)
                        .all(|v| v.is_finite())
                    && sim.inflated_length_mm.is_finite();
                assert!(finite, "{name}: converged with a non-finite number");
                let stable = if sim.stats.stable {
                    ""
                } else {
                    "  (not stable)"
                };
                format!(
                    "converged  {:>3} its {ms:>7.0} ms  length {:.1} mm{stable}",
                    sim.stats.iterations, sim.inflated_length_mm
                )
            }
            (Err(SimulateError::Design(e)), Expect::Invalid(field)) if e.field == field => {
                format!("refused as expected: {e}")
            }
            (Err(e @ SimulateError::NoTubeState { .. }), Expect::NoTubeState) => {
                format!("refused as expected: {e}")
            }
            (
                Err(e @ (SimulateError::Solve { .. } | SimulateError::Burst { .. })),
                Expect::ConvergesOrFails,
            ) => {
                self.failed += 1;
                format!("failed, typed: {e}")
            }
            (outcome, expect) => panic!(
                "{name}: expected {expect:?}, got {:?}",
                outcome.as_ref().map(|s| s.stats)
            ),
        };
        self.push(format!("{name:<44} {line}"));
    }

    /// Runs the design pipeline on a target at draft fidelity with a tiny
    /// search budget and a short refine (none for very long targets), and
    /// checks its outcome against `expect`.
    fn design(&mut self, name: &str, target: Result<Curve, CurveError>, expect: ExpectDesign) {
        let target = match (target, expect) {
            (Ok(curve), ExpectDesign::Within(_)) => curve,
            (Err(e @ CurveError::TooFewPoints { .. }), ExpectDesign::TooFewPoints) => {
                self.push(format!("{name:<44} refused as expected: {e}"));
                return;
            }
            (target, expect) => panic!("{name}: expected {expect:?}, got {target:?}"),
        };
        let ExpectDesign::Within(ceiling) = expect else {
            unreachable!("matched above")
        };
        let settings = UserSettings {
            fidelity: Fidelity::Draft,
            budget: Some(3),
            threads: 1,
            ..UserSettings::default()
        };
        let refine = match target.length() > NO_REFINE_BEYOND_MM {
            true => 0,
            false => STRESS_REFINE,
        };
        // A long helix as a train of some forty patches takes more than 15
        // minutes here (one patch per bend: a few); it runs KSA's layout.
        let overrides = TuningOverrides {
            refine_budget: Some(refine),
            trains: (target.length() > NO_REFINE_BEYOND_MM).then_some(false),
            ..TuningOverrides::default()
        };
        let plan = Plan::resolve(settings, &overrides).expect("valid settings");
        let started = Instant::now();
        let outcome = design(&target, &plan, &AtomicBool::new(false), &mut |_| {});
        let elapsed = started.elapsed().as_secs_f64();
        let o = outcome.unwrap_or_else(|e| panic!("{name}: expected a design, got {e}"));
        let finite = o
            .simulation
            .centreline
            .points()
            .iter()
            .all(|p| p.iter().all(|v| v.is_finite()));
        assert!(finite, "{name}: NaN in the result");
        assert!(o.design.validate().is_ok(), "{name}: the design is invalid");
        // The spread at the default tolerances: finite, or the reason why not.
        match (&o.spread, &o.spread_failed) {
            (Some(s), _) => assert!(
                s.rms_mm.is_finite() && s.tip_rms_mm.is_finite(),
                "{name}: spread {s:?}"
            ),
            (None, reason) => assert!(reason.is_some(), "{name}: no spread and no reason"),
        }
        let error = o.metrics.shape_error_percent;
        assert!(
            error <= ceiling,
            "{name}: shape error {error:.2} % above its {ceiling} %"
        );
        self.push(format!(
            "{name:<44} designed   {} patches, shape error {error:.2} % (≤ {ceiling} %), {elapsed:.1} s",
            o.design.patches.len(),
        ));
    }

    /// Records a case's line, and prints it at once (seen with
    /// `--nocapture` while the suite runs).
    fn push(&mut self, line: String) {
        eprintln!("{line}");
        self.lines.push(line);
    }

    fn report(&self, suite: &str) {
        println!("\n{suite}:");
        for line in &self.lines {
            println!("  {line}");
        }
    }
}

#[test]
fn abusive_designs_converge_or_fail_with_a_typed_error() {
    let mut t = Tally::default();
    let mid = patch(0.0, 146.0, 20.0, 2.0, 0.0);
    // A patch of a hundredth the stiffness leaves a nearly bare tube whose
    // one slightly stiffer spot sets off the bare wall's soft mode at 20 kPa:
    // Newton does not settle within its limits, here or on the default mesh
    // (60 iterations, relative residual 1e-4). With the facets loaded by the
    // bare pressure (before `fe::pressure::facet_load_factor`) this 2 mm
    // mesh ended "converged" in a burst state, hoop stretch 243 and 2.8 m
    // long; a typed failure is the honest answer.
    for (factor, name, expect) in [
        (1000.0, "patch stiffness ×1000", Expect::Converges),
        (0.01, "patch stiffness ×0.01", Expect::ConvergesOrFails),
    ] {
        let mut d = with_patches(vec![mid]);
        d.patch.material.law = Law::NeoHookean {
            mu_mpa: 1.3 * factor,
        };
        t.simulate(name, &d, expect);
    }
    let converges = Expect::Converges;
    let one_patch = [
        ("width 0.1 mm", patch(0.0, 146.0, 20.0, 0.1, 0.0), converges),
        (
            "width 20 mm (whole circumference)",
            patch(0.0, 146.0, 20.0, 20.0, 0.0),
            converges,
        ),
        ("Θ = +89°", patch(0.0, 146.0, 20.0, 2.0, 89.0), converges),
        ("Θ = −89°", patch(0.0, 146.0, 20.0, 2.0, -89.0), converges),
        (
            "patch across the seam",
            patch(19.5, 146.0, 20.0, 3.0, 20.0),
            converges,
        ),
        (
            "patch hanging off the base",
            patch(0.0, 2.0, 20.0, 2.0, 0.0),
            converges,
        ),
        (
            "patch hanging off the far end",
            patch(0.0, 290.0, 20.0, 2.0, 0.0),
            converges,
        ),
        (
            "patch wholly off the balloon",
            patch(0.0, 400.0, 20.0, 2.0, 0.0),
            Expect::Invalid("patches[0].y_mm"),
        ),
        (
            "negative width",
            patch(0.0, 146.0, 20.0, -2.0, 0.0),
            Expect::Invalid("patches[0].w_mm"),
        ),
    ];
    for (name, p, expect) in one_patch {
        t.simulate(name, &with_patches(vec![p]), expect);
    }
    t.simulate(
        "three overlapping patches",
        &with_patches(vec![
            patch(0.0, 140.0, 20.0, 2.0, 0.0),
            patch(0.5, 146.0, 20.0, 2.0, 30.0),
            patch(1.0, 150.0, 20.0, 2.0, -30.0),
        ]),
        converges,
    );

    // The incompressible neo-Hookean tube's pressure maximum: p R0 / (μ t0) = 0.749868.
    let (mu, r0, t0) = (0.317, 3.18, 0.183);
    let p_max_kpa = 0.749868 * mu * t0 / r0 * 1e3;
    for (fraction, name, expect) in [
        (0.98, "pressure 2 % below the limit point", converges),
        (1.0, "pressure at the limit point", Expect::NoTubeState),
        (
            1.02,
            "pressure 2 % above the limit point",
            Expect::NoTubeState,
        ),
    ] {
        let mut d = with_patches(vec![mid]);
        d.balloon.material = Material::incompressible(Law::NeoHookean { mu_mpa: mu });
        d.pressure_kpa = p_max_kpa * fraction;
        t.simulate(name, &d, expect);
    }
    // The incompressible Arruda–Boyce wall stiffens and the bare tube holds
    // 500 kPa (hoop stretch 6.0); with the patch Newton settles where the
    // wall by it has bulged to a hoop stretch of 15, which is refused as a
    // burst. The paper's compressible wall thins instead and passes a hoop
    // stretch of 12 (past any latex balloon's burst) near 33 kPa.
    let mut d = with_patches(vec![mid]).with_compressibility(Compressibility::Incompressible);
    d.pressure_kpa = 500.0;
    t.simulate(
        "very high pressure (500 kPa), incompressible",
        &d,
        Expect::ConvergesOrFails,
    );
    // At 30 kPa the bare wall stands at hoop stretch 10.4, near its burst:
    // the patched tube may not settle (here it does not, 72 iterations),
    // and must not end in a burst state called converged (with the facets
    // loaded by the bare pressure this 2 mm mesh ended at hoop stretch 404).
    let mut d = with_patches(vec![mid]);
    let fails_typed = Expect::ConvergesOrFails;
    for (kpa, expect) in [(30.0, fails_typed), (40.0, Expect::NoTubeState)] {
        d.pressure_kpa = kpa;
        t.simulate(&format!("{kpa} kPa on the paper's balloon"), &d, expect);
    }

    let mut rng = SeededRng::new(6);
    let long: Vec<Patch> = (0..30)
        .map(|i| {
            patch(
                20.0 * rng.uniform(),
                16.0 + 32.0 * i as f64,
                15.0,
                2.0,
                60.0 * rng.uniform() - 30.0,
            )
        })
        .collect();
    let mut d = short(1000.0, long);
    d.pressure_kpa = 20.0;
    t.simulate("1 m balloon with 30 patches", &d, converges);
    t.simulate(
        "2 cm balloon",
        &short(20.0, vec![patch(0.0, 10.0, 8.0, 2.0, 20.0)]),
        converges,
    );
    t.report("abusive designs");
}

fn curve(points: Vec<Point>) -> Result<Curve, patchwork_core::CurveError> {
    Curve::from_points(points)
}

#[test]
fn abusive_target_curves_design_or_fail_with_a_typed_error() {
    let mut t = Tally::default();
    t.design(
        "straight",
        Preset::from_name("line", serde_json::json!({"length_mm": 300}))
            .unwrap()
            .curve(None),
        ExpectDesign::Within(0.1),
    );
    t.design(
        "planar with inflections (sine)",
        curve(
            (0..400)
                .map(|i| {
                    let x = i as f64 * 0.75;
                    Point::new(x, 30.0 * (x / 30.0).sin(), 0.0)
                })
                .collect(),
        ),
        ExpectDesign::Within(0.5),
    );
    t.design(
        "cusp (astroid arc)",
        curve(
            (0..400)
                .map(|i| {
                    let s = 0.2 + (std::f64::consts::PI - 0.4) * i as f64 / 399.0;
                    Point::new(80.0 * s.cos().powi(3), 80.0 * s.sin().powi(3), 0.0)
                })
                .collect(),
        ),
        ExpectDesign::Within(5.0),
    );
    let mut rng = SeededRng::new(11);
    t.design(
        "helix with 1 % noise",
        Preset::helix(20.0, 60.0, 1.5)
            .curve(None)
            .map(|c| {
                let scale = 0.01 * c.length() / 10.0;
                Curve::from_points(
                    c.points()
                        .iter()
                        .map(|p| p + Point::new(rng.normal(), rng.normal(), rng.normal()) * scale)
                        .collect(),
                )
            })
            .and_then(|c| c),
        // The noise (0.05 % of the length per coordinate) is found and
        // smoothed away before KSA: 0.05 % at this tiny budget, against the
        // smoothed target (5.9 % when the noisy torsion set the angles).
        ExpectDesign::Within(0.5),
    );
    t.design(
        "self-intersecting (lemniscate)",
        curve(
            (0..400)
                .map(|i| {
                    let s = std::f64::consts::TAU * i as f64 / 400.0;
                    Point::new(60.0 * s.sin(), 60.0 * s.sin() * s.cos(), 0.0)
                })
                .collect(),
        ),
        ExpectDesign::Within(1.0),
    );
    t.design(
        "extremely tight (helix radius 2 mm)",
        Preset::helix(2.0, 8.0, 3.0).curve(None),
        ExpectDesign::Within(6.0),
    );
    t.design(
        "two points only",
        curve(vec![Point::new(0.0, 0.0, 0.0), Point::new(1.0, 0.0, 0.0)]),
        ExpectDesign::TooFewPoints,
    );
    t.report("abusive target curves");
}

/// About 1.3 m: a 360 mm balloon of the paper's latex, designed without
/// the refine (a 2 m helix, its 545 mm balloon, takes over 15 minutes on 2
/// cores). About 4 minutes: run on request.
#[test]
#[ignore = "about 4 minutes: run on request (-- --ignored)"]
fn a_very_long_target_designs_without_the_refine() {
    let mut t = Tally::default();
    t.design(
        "very long (helix, about 1.3 m)",
        Preset::helix(50.0, 100.0, 4.0).curve(Some(1400)),
        ExpectDesign::Within(20.0),
    );
    t.report("a very long target");
}

/// The first patch that lies entirely off the balloon: its rotated
/// rectangle's axial extent y ± (H|cos Θ| + W|sin Θ|)/2 misses 0..L. The
/// random designs below break no other rule of a valid design (finite
/// positions within reach, positive sizes, |Θ| < 90°, 1–25 kPa).
fn first_patch_off_the_balloon(d: &Design) -> Option<usize> {
    let length = d.balloon.length_mm;
    d.patches.iter().position(|p| {
        let theta = p.theta_deg.to_radians();
        let half = 0.5 * (p.h_mm * theta.cos().abs() + p.w_mm * theta.sin().abs());
        p.y_mm + half <= 0.0 || p.y_mm - half >= length
    })
}

/// Random designs far outside the fabrication bounds (positions off the
/// balloon, widths 0.1–10 mm, angles up to ±89°, 1–25 kPa: at 25 kPa the
/// paper's balloon is stretched 7.6 round, about where a real one bursts):
/// a design that does not validate is refused naming the field; one that
/// does converges or fails with a typed error, and at most 5 of 100 fail.
/// (Measured: one fails on this 2 mm mesh, four bands up to 9.8 mm wide
/// and 57 mm long at 23 kPa, stalling in the continuation at a fifth of the
/// patches' stiffness; on the default 0.5 mm mesh it converges.)
#[test]
fn random_designs_far_outside_the_bounds_converge_or_are_refused() {
    let mut t = Tally::default();
    let mut rng = SeededRng::new(424242);
    let mut cases = Vec::new();
    for i in 0..100 {
        let n = 1 + (rng.uniform() * 8.0) as usize;
        let patches = (0..n)
            .map(|_| {
                patch(
                    40.0 * rng.uniform() - 10.0,
                    320.0 * rng.uniform() - 14.0,
                    1.0 + 60.0 * rng.uniform(),
                    0.1 + 10.0 * rng.uniform(),
                    178.0 * rng.uniform() - 89.0,
                )
            })
            .collect();
        let mut d = with_patches(patches);
        d.pressure_kpa = 1.0 + 24.0 * rng.uniform();
        let expect = match first_patch_off_the_balloon(&d) {
            None => Expect::ConvergesOrFails,
            Some(i) => Expect::Invalid(format!("patches[{i}].y_mm").leak()),
        };
        cases.push((format!("random design {i}"), d, expect));
    }
    let refused = cases
        .iter()
        .filter(|(_, _, expect)| *expect != Expect::ConvergesOrFails)
        .count();
    t.simulate_all(cases);
    t.report("random abusive designs");
    assert!(
        (1..=50).contains(&refused),
        "{refused} of 100 designs off the balloon: both kinds of case must be drawn"
    );
    assert!(
        t.failed <= 5,
        "{} of 100 designs failed to converge",
        t.failed
    );
}
