//! The plan's stages and budgets as each preset resolves them.

use super::*;
use crate::inverse::Fidelity;

fn plan(fidelity: Fidelity, overrides: TuningOverrides) -> Plan {
    let settings = UserSettings {
        fidelity,
        ..UserSettings::default()
    };
    Plan::resolve(settings, &overrides).unwrap()
}

#[test]
fn every_stage_with_a_budget_of_its_own_shows_it() {
    let draft = plan(Fidelity::Draft, TuningOverrides::default());
    let tuning = draft.tuning();
    assert!(tuning.search_patience > 0 && tuning.refine_budget > 0);
    let expected = format!(
        "reach; search: {} evaluations, ends after {} without a better design; verify; \
         length; refine: {} solves; layout: up to 5 layouts, {} solves each; \
         spread: 5 sources per patch and 3, at the tolerances: linearised, the large \
         sources solved both ways (the patches' on the graded 2 mm (bare stretches 6 mm) \
         model)",
        draft.search_budget(),
        tuning.search_patience,
        tuning.refine_budget,
        tuning.refine_budget
    );
    assert_eq!(draft.describe_budgets(), expected);
    let limited = Plan::resolve(
        UserSettings {
            time_limit_s: Some(60.0),
            ..draft.settings().clone()
        },
        &TuningOverrides::default(),
    )
    .unwrap();
    assert_eq!(
        limited.describe_budgets(),
        format!("{expected}; the whole run: at most 60 s")
    );
    assert_eq!(
        draft.describe(),
        "seed → reach → search → verify → length → refine → layout → spread"
    );

    let standard = plan(
        Fidelity::Standard,
        TuningOverrides {
            search_patience: Some(0),
            polish_budget: Some(30),
            ..TuningOverrides::default()
        },
    );
    let budgets = standard.describe_budgets();
    let last = standard
        .tuning()
        .final_refine
        .expect("standard's final refine");
    let shared = standard.tuning().refine_budget;
    let staging = shared.min(last.staging_solves);
    for part in [
        format!("search: {} evaluations;", standard.search_budget()),
        "polish: 30 evaluations;".to_string(),
        format!("refine: {staging} solves;"),
        format!(
            "final refine: {shared} solves with the refine's, on the {} model",
            last.mesh
        ),
    ] {
        assert!(budgets.contains(&part), "{part:?} not in {budgets:?}");
    }
    assert!(budgets.ends_with(SPREAD_MODELS), "{budgets}");
}

/// The spread's models, as every preset sets them.
const SPREAD_MODELS: &str =
    "solved both ways (the patches' on the graded 2 mm (bare stretches 6 mm) model)";

#[test]
fn the_checks_and_the_robust_refine_follow_the_spread() {
    let patches = SPREAD_MODELS;
    let fine = plan(Fidelity::Fine, TuningOverrides::default());
    let checked = format!("{patches}; a Monte-Carlo check of 200 designs");
    assert!(fine.describe_budgets().ends_with(&checked));
    // The robust refine follows the spread, and the check is of the
    // design that stands: after it.
    let robust = TuningOverrides {
        robust: Some(true),
        ..TuningOverrides::default()
    };
    let budgets = plan(Fidelity::Fine, robust.clone()).describe_budgets();
    let robust_part = "robust: 270 solves, weighing the spread's 4 largest sources at most; \
                       a Monte-Carlo check of 200 designs";
    assert!(budgets.ends_with(robust_part), "{budgets}");
    assert!(budgets.contains(&format!("{patches}; robust")), "{budgets}");
    let unspread = TuningOverrides {
        spread: Some(false),
        ..robust
    };
    let refused = Plan::resolve(UserSettings::default(), &unspread).unwrap_err();
    assert_eq!(refused.field, "tuning.robust");
}

/// A refine tolerance given replaces the preset's; one outside 0–50 % is
/// refused, naming the field.
#[test]
fn the_refine_tolerance_is_the_request_s_within_range() {
    let set = |t: f64| TuningOverrides {
        refine_tolerance: Some(t),
        ..TuningOverrides::default()
    };
    let tuning = |p: Plan| p.tuning().refine_tolerance;
    assert_eq!(tuning(plan(Fidelity::Standard, set(0.0))), 0.0);
    assert_eq!(tuning(plan(Fidelity::Fine, set(0.3))), 0.3);
    for bad in [-0.1, 51.0, f64::NAN] {
        let settings = UserSettings::default();
        let refused = Plan::resolve(settings, &set(bad)).unwrap_err();
        assert_eq!(refused.field, "tuning.refine_tolerance", "{bad}");
    }
}
