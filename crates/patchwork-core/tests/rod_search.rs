//! A design run whose search runs on the rod model (tuning `rod_search`):
//! the rod table is solved once for the scene and kept, the search counts
//! ten rod evaluations as one of its budget, and the design is verified and
//! refined on FE as any other.

use std::sync::atomic::AtomicBool;

use patchwork_core::curve::{Curve, Preset};
use patchwork_core::inverse::{Fidelity, Plan, StageName, TuningOverrides, UserSettings, design};

/// The hook preset's curve.
fn hook() -> Curve {
    let preset = Preset::from_name("hook", serde_json::json!({})).unwrap();
    preset.curve(None).unwrap()
}

/// A search on the rod, without the spread stage.
fn on_the_rod() -> TuningOverrides {
    TuningOverrides {
        rod_search: Some(true),
        spread: Some(false),
        ..TuningOverrides::default()
    }
}

#[test]
fn a_search_on_the_rod_hands_the_refine_a_better_design_than_its_seed() {
    let target = hook();
    let budget = 60;
    let settings = UserSettings {
        fidelity: Fidelity::Draft,
        budget: Some(budget),
        ..UserSettings::default()
    };
    let overrides = on_the_rod();
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

/// A search on the rod resumed from a checkpoint taken after one of its
/// corrections corrects where the interrupted one did: the same design in
/// the same evaluations as the run that was not interrupted.
#[test]
fn a_search_on_the_rod_resumes_where_it_was_corrected() {
    use patchwork_core::inverse::{
        Caches, DesignCheckpoint, DesignProgress, Observer, design_resumable,
    };
    /// Keeps every checkpoint.
    struct Saving(Vec<DesignCheckpoint>);
    impl Observer for Saving {
        fn progress(&mut self, _: &DesignProgress) {}
        fn checkpoint(&mut self, c: &DesignCheckpoint) {
            self.0.push(c.clone());
        }
    }
    let target = hook();
    let settings = UserSettings {
        fidelity: Fidelity::Draft,
        budget: Some(80),
        threads: 1,
        ..UserSettings::default()
    };
    let overrides = on_the_rod();
    let plan = Plan::resolve(settings, &overrides).expect("valid settings");
    let never = AtomicBool::new(false);
    let mut saving = Saving(Vec::new());
    let whole = design_resumable(
        &target,
        &plan,
        None,
        &Caches::default(),
        &never,
        &mut saving,
    )
    .expect("a design");
    // A checkpoint after the first correction, with generations to come.
    let corrected =
        |c: &&DesignCheckpoint| (c.rod.as_ref()).is_some_and(|r| r.corrected_at != c.seed_patches);
    let saved = &saving.0[..saving.0.len() - 2];
    let checkpoint = saved
        .iter()
        .find(corrected)
        .expect("a corrected checkpoint");
    let json = serde_json::to_string(checkpoint).unwrap();
    let checkpoint: DesignCheckpoint = serde_json::from_str(&json).unwrap();
    let resumed = design_resumable(
        &target,
        &plan,
        Some(checkpoint),
        &Caches::default(),
        &never,
        &mut |_: &DesignProgress| {},
    )
    .expect("a design");
    assert_eq!(resumed.design, whole.design);
    assert_eq!(resumed.evaluations, whole.evaluations);
    assert_eq!(resumed.search_objective, whole.search_objective);
}

/// A budget too small for two of the rod's rounds searches on FE and says
/// so: the search spends its budget in FE solves, and no rod table is
/// solved for it.
#[test]
fn a_budget_too_small_for_the_rounds_searches_on_fe_and_says_why() {
    let budget = 12;
    let settings = UserSettings {
        fidelity: Fidelity::Draft,
        budget: Some(budget),
        ..UserSettings::default()
    };
    let plan = Plan::resolve(settings, &on_the_rod()).expect("valid settings");
    let o = design(&hook(), &plan, &AtomicBool::new(false), &mut |_| {}).expect("a design");
    let why = o.rod_skipped.as_deref().unwrap_or_default();
    assert!(why.contains("budget of 12"), "{why}");
    let search = o.stage_times.iter().find(|s| s.stage == StageName::Search);
    let solves = search.expect("a search stage").evaluations;
    assert!((2..=budget).contains(&solves), "{solves} solves");
}
