use std::cell::Cell;
use std::time::Duration;

use super::*;
use crate::design::Patch;
use crate::fe::mesh::MeshSpec;
use crate::inverse::memo::KEEP;
use crate::inverse::reach::PatchResponse;

/// A complete table for `bounds`, each entry's curvature `mark`.
fn table(bounds: &VariableBounds, mark: f64) -> ReachTable {
    let entries = ReachTable::grid(bounds)
        .into_iter()
        .map(|(width_mm, theta_deg)| PatchResponse {
            width_mm,
            theta_deg,
            curvature_per_mm: mark,
            torsion_per_mm: 0.0,
            peak_curvature_per_mm: mark,
        })
        .collect();
    ReachTable {
        patch_length_mm: bounds.h_max_mm,
        entries,
    }
}

/// A scene no other test uses: its key is its own in the process's memory.
fn scene(pressure_kpa: f64) -> Design {
    Design {
        pressure_kpa,
        ..Design::reference(Vec::new())
    }
}

#[test]
fn the_key_is_the_scene_bounds_and_model_not_the_patches_length_threads_or_time() {
    let bounds = VariableBounds::default();
    let model = SimulateOptions {
        mesh: MeshSpec::uniform(1.0),
        ..SimulateOptions::default()
    };
    let base = scene(20.0);
    let reference = key(&base, &bounds, &model);
    let mut other = base.clone();
    other.balloon.length_mm += 50.0;
    other.patches.push(Patch {
        x_mm: 0.0,
        y_mm: 40.0,
        h_mm: 20.0,
        w_mm: 2.0,
        theta_deg: 10.0,
    });
    let threaded = SimulateOptions {
        threads: 2,
        time_limit: Some(Duration::from_secs(5)),
        ..model
    };
    assert_eq!(key(&other, &bounds, &threaded), reference);
    let changed = [
        key(&scene(20.5), &bounds, &model),
        key(
            &base,
            &VariableBounds {
                w_max_mm: bounds.w_max_mm + 0.5,
                ..bounds
            },
            &model,
        ),
        key(
            &base,
            &bounds,
            &SimulateOptions {
                mesh: MeshSpec::uniform(0.5),
                ..model
            },
        ),
    ];
    for k in changed {
        assert_ne!(k, reference);
    }
}

#[test]
fn a_complete_table_is_computed_once_an_incomplete_one_every_time() {
    let bounds = VariableBounds::default();
    let complete = |t: &ReachTable| t.is_complete(&bounds);
    let computed = Cell::new(0);
    let compute = |mark: f64, drop: usize| {
        computed.set(computed.get() + 1);
        let mut t = table(&bounds, mark);
        t.entries.truncate(t.entries.len() - drop);
        Ok(t)
    };
    let whole = key(&scene(17.25), &bounds, &SimulateOptions::default());
    let first = table_for(&whole, || compute(1.0, 0), complete).unwrap();
    let again = table_for(&whole, || compute(2.0, 0), complete).unwrap();
    assert_eq!((computed.get(), &again), (1, &first));

    computed.set(0);
    let partial = key(&scene(17.5), &bounds, &SimulateOptions::default());
    let short = table_for(&partial, || compute(1.0, 1), complete).unwrap();
    assert!(!short.is_complete(&bounds));
    let full = table_for(&partial, || compute(3.0, 0), complete).unwrap();
    assert_eq!(computed.get(), 2);
    assert_eq!(full.entries[0].curvature_per_mm, 3.0);
}

#[test]
fn memory_keeps_no_more_than_keep_tables() {
    let bounds = VariableBounds::default();
    let complete = |t: &ReachTable| t.is_complete(&bounds);
    let keys: Vec<String> = (0..=KEEP)
        .map(|i| {
            key(
                &scene(3.0 + 0.125 * i as f64),
                &bounds,
                &SimulateOptions::default(),
            )
        })
        .collect();
    for (i, k) in keys.iter().enumerate() {
        table_for(k, || Ok(table(&bounds, i as f64)), complete).unwrap();
    }
    // The first was pushed out by the KEEP after it (tests running beside
    // this one may push out more, never fewer).
    let recomputed = Cell::new(false);
    let first = table_for(
        &keys[0],
        || {
            recomputed.set(true);
            Ok(table(&bounds, -1.0))
        },
        complete,
    )
    .unwrap();
    assert!(recomputed.get() && first.entries[0].curvature_per_mm == -1.0);
    assert!(KEPT.len() <= KEEP);
}
