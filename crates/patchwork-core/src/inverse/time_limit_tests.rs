//! The time limit on a whole run: passed during the seed, every later stage
//! but the verification is skipped, and the outcome is a verified design
//! that says what the limit cut short.

use std::sync::atomic::AtomicBool;

use super::*;
use crate::curve::presets::Preset;
use crate::inverse::{Fidelity, Plan, SearchStop, TuningOverrides, UserSettings};

#[test]
fn a_limit_passed_at_the_seed_leaves_a_verified_seed_that_says_so() {
    let target = Preset::from_name("hook", serde_json::json!({}))
        .unwrap()
        .curve(None)
        .unwrap();
    let settings = UserSettings {
        fidelity: Fidelity::Draft,
        time_limit_s: Some(1e-3),
        ..UserSettings::default()
    };
    // A search asked on the rod says it did not run there.
    let overrides = TuningOverrides {
        rod_search: Some(true),
        ..TuningOverrides::default()
    };
    let plan = Plan::resolve(settings, &overrides).unwrap();
    let o = design(&target, &plan, &AtomicBool::new(false), &mut |_| {}).unwrap();
    let limited = o.time_limited.clone().expect("the limit cut the run short");
    assert_eq!(limited.limit_s, 1e-3);
    assert_eq!(limited.reached_in, StageName::Seed);
    let planned: Vec<StageName> = plan.stages().iter().map(|s| s.name()).collect();
    let skipped: Vec<StageName> = (planned.iter().copied())
        .filter(|&s| s != StageName::Verify)
        .collect();
    assert_eq!(limited.skipped, skipped);
    assert!(skipped.contains(&StageName::Search) && skipped.contains(&StageName::Spread));
    let ran: Vec<StageName> = o.stage_times.iter().map(|t| t.stage).collect();
    assert_eq!(ran, vec![StageName::Seed, StageName::Verify]);
    // The seed's design, verified: its figures are measured, not missing.
    assert_eq!(o.design.patches, o.seed_design.patches);
    assert!(o.metrics.shape_error_percent.is_finite());
    assert!(o.as_given.shape_error_percent.is_finite());
    assert!(o.spread.is_none());
    let why = o.spread_failed.as_deref().unwrap_or_default();
    assert!(
        why.contains("time limit") && why.contains("spread"),
        "{why}"
    );
    let why = o.rod_skipped.as_deref().unwrap_or_default();
    assert!(
        why.contains("time limit") && why.contains("search"),
        "{why}"
    );
    assert_ne!(o.termination, SearchEnd::Search(SearchStop::TimeLimit));
    if o.metrics.shape_error_percent > super::super::shortfall::HIGH_ERROR_PERCENT {
        assert_eq!(
            o.shortfalls.first(),
            Some(&super::super::shortfall::Shortfall::TimeLimit { limit_s: 1e-3 })
        );
    }
    assert!(
        limited
            .message()
            .contains("reached in the seed; skipped: reach, search")
    );
}
