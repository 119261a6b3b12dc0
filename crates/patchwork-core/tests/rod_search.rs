//! A design run whose search runs on the rod model (tuning `rod_search`):
//! the rod table is solved once for the scene and kept, the search counts
//! ten rod evaluations as one of its budget, and the design is verified and
//! refined on FE as any other.

use std::sync::atomic::AtomicBool;

use patchwork_core::curve::Preset;
use patchwork_core::inverse::{Fidelity, Plan, StageName, TuningOverrides, UserSettings, design};

#[test]
fn a_search_on_the_rod_hands_the_refine_a_better_design_than_its_seed() {
    let target = Preset::from_name("hook", serde_json::json!({}))
        .unwrap()
        .curve(None)
        .unwrap();
    let budget = 60;
    let settings = UserSettings {
        fidelity: Fidelity::Draft,
        budget: Some(budget),
        ..UserSettings::default()
    };
    let overrides = TuningOverrides {
        rod_search: Some(true),
        spread: Some(false),
        ..TuningOverrides::default()
    };
    let plan = Plan::resolve(settings, &overrides).expect("valid settings");
    let run = || design(&target, &plan, &AtomicBool::new(false), &mut |_| {}).expect("a design");
    let first = run();
    // On the rod both objectives are the rod's: the search kept a better
    // design than the seed.
    assert!(
        first.search_objective < first.seed_objective,
        "{} against the seed's {}",
        first.search_objective,
        first.seed_objective
    );
    assert!(
        first.metrics.shape_error_percent < 0.3,
        "{} %",
        first.metrics.shape_error_percent
    );
    let search = |o: &patchwork_core::inverse::DesignOutcome| {
        let s = o.stage_times.iter().find(|s| s.stage == StageName::Search);
        s.expect("a search stage").evaluations
    };
    // The table's 73 solves (the bare balloon and 72 one-patch ones) and
    // the seed on the verification model, then the budget in units of
    // `ROD_EVALUATIONS` rod evaluations.
    assert!(search(&first) <= 73 + 1 + budget, "{}", search(&first));
    // The second run of the scene reads the table back: no table solves,
    // and the same design.
    let second = run();
    assert!(search(&second) <= 1 + budget, "{}", search(&second));
    assert_eq!(second.design, first.design);
}
