//! The robust refine (tuning `robust`): after the spread, the design refined
//! for the shape error expected at the tolerances, √(nominal² + spread²),
//! and kept only if that is lower than the nominal design's.
//!
//! An arc of radius 80 mm through 120°, `draft` with a short search: its
//! spread is mostly the balloon's own (wall, pressure, modulus), which the
//! patches can only make the balloon more or less sensitive to. The refine
//! must lower its own objective (the expected error over the sources it
//! weighs), the figures must add up, and the design the run ends with must
//! be the one with the lower expected error, its spread and metrics the
//! outcome's. The outcome's stage times name every stage the plan took.

use std::sync::atomic::AtomicBool;

use patchwork_core::curve::presets::Preset;
use patchwork_core::inverse::{
    Expected, Fidelity, Plan, StageName, StageTime, TuningOverrides, UserSettings, design,
};

#[test]
fn a_robust_design_lowers_the_shape_error_expected_at_the_tolerances() {
    let arc = Preset::from_name(
        "arc",
        serde_json::json!({"radius_mm": 80.0, "angle_deg": 120.0}),
    );
    let target = arc.unwrap().curve(None).unwrap();
    let settings = UserSettings {
        fidelity: Fidelity::Draft,
        budget: Some(40),
        threads: patchwork_core::available_cores(),
        ..UserSettings::default()
    };
    let overrides = TuningOverrides {
        robust: Some(true),
        ..TuningOverrides::default()
    };
    let plan = Plan::resolve(settings, &overrides).expect("valid settings");
    let o = design(&target, &plan, &AtomicBool::new(false), &mut |_| {}).expect("a design");
    assert_eq!(o.robust_skipped, None);
    // Where the time went: the seed and every planned stage, in order,
    // their solves adding up to the run's (the reach table's apart) and
    // their times to at most its.
    let ran: Vec<StageName> = o.stage_times.iter().map(|t| t.stage).collect();
    let planned: Vec<StageName> = std::iter::once(StageName::Seed)
        .chain(plan.stages().iter().map(|s| s.name()))
        .collect();
    assert_eq!(ran, planned);
    let (reach, budgeted): (Vec<&StageTime>, Vec<&StageTime>) =
        (o.stage_times.iter()).partition(|t| t.stage == StageName::Reach);
    let solves: usize = budgeted.iter().map(|t| t.evaluations).sum();
    assert_eq!(solves, o.evaluations, "{:?}", o.stage_times);
    // The reach table's 21 balloons, solved in this process's first run.
    let reach: Vec<usize> = reach.iter().map(|t| t.evaluations).collect();
    assert_eq!(reach, [21], "{:?}", o.stage_times);
    let seconds: f64 = o.stage_times.iter().map(|t| t.seconds).sum();
    let elapsed = o.elapsed.as_secs_f64();
    assert!(
        seconds <= elapsed && seconds > 0.5 * elapsed,
        "{seconds} s of {elapsed} s"
    );
    let r = o.robust.expect("the robust refine ran");
    println!("{r:#?}");
    assert!(
        !r.sources.is_empty() && r.sources.len() <= 4,
        "{:?}",
        r.sources
    );
    assert!(
        r.weighed_after_percent < 0.95 * r.weighed_before_percent,
        "the robust refine did not lower its objective: {} → {} %",
        r.weighed_before_percent,
        r.weighed_after_percent
    );
    for e in [r.nominal_design, r.robust_design] {
        let hypot = e.shape_error_percent.hypot(e.spread_percent);
        assert!((e.expected_percent - hypot).abs() < 1e-12, "{e:?}");
        assert!(e.expected_percent.is_finite(), "{e:?}");
    }
    let (stands, other): (Expected, Expected) = match r.kept {
        true => (r.robust_design, r.nominal_design),
        false => (r.nominal_design, r.robust_design),
    };
    assert!(stands.expected_percent <= other.expected_percent, "{r:?}");
    let spread = o.spread.expect("the spread of the design that stands");
    assert!((spread.rms_percent - stands.spread_percent).abs() < 1e-9);
    let shape = o.metrics.shape_error_percent;
    assert!(
        (shape - stands.shape_error_percent).abs() < 1e-6,
        "{shape} against {stands:?}"
    );
}
