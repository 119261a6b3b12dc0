use super::*;
use crate::curve::presets::{ArcParams, Preset};

fn balloon(length: f64, patches: Vec<Patch>) -> Design {
    let mut design = Design::reference(patches);
    design.balloon.length_mm = length;
    design
}

fn patch(x: f64, y: f64, h: f64) -> Patch {
    Patch {
        x_mm: x,
        y_mm: y,
        h_mm: h,
        w_mm: 1.5,
        theta_deg: 0.0,
    }
}

fn arc(radius_mm: f64, angle_deg: f64) -> Curve {
    Preset::Arc(ArcParams {
        radius_mm,
        angle_deg,
    })
    .generate(400)
    .unwrap()
}

/// κ per sample as KSA marks by.
fn curvature(curve: &Curve) -> Vec<f64> {
    let options = crate::curve::AnalysisOptions {
        scheme: KsaParams::default().scheme,
        ..Default::default()
    };
    crate::curve::analyse(curve, &options).curvature
}

/// KSA with trains of patches at most 30 mm long.
fn trains() -> KsaParams {
    KsaParams {
        max_patch_mm: Some(30.0),
        ..KsaParams::default()
    }
}

#[test]
fn a_gentle_arc_gets_patches_where_the_design_has_none() {
    // r = 150 mm: κ = 0.0067 mm⁻¹, under KSA's 0.01 but over 0.004.
    let arc = arc(150.0, 180.0);
    let empty = balloon(300.0, vec![]);
    let params = trains();
    let finer = with_gentle_bends(&empty, &arc, 0.01, &params, 10.0).unwrap();
    assert!(finer.patches.len() >= 10, "{:?}", finer.patches);
    assert!(finer.patches.iter().all(|p| p.h_mm <= 30.0 + 1e-9));
    // A design that already covers the whole balloon gets nothing more.
    let covered = balloon(300.0, vec![patch(0.0, 150.0, 300.0)]);
    assert_eq!(with_gentle_bends(&covered, &arc, 0.01, &params, 10.0), None);
}

/// A candidate no patch comes near is added whole; one a patch half covers
/// keeps its longest free stretch (1 mm clear of the patches), if that is
/// at least the shortest patch long; one covered but for slivers is not.
#[test]
fn a_half_covered_bend_gets_a_patch_on_its_free_part() {
    let candidate = Patch {
        w_mm: 2.0,
        theta_deg: 10.0,
        ..patch(3.0, 150.0, 20.0)
    };
    let far = [patch(0.0, 100.0, 20.0)];
    assert_eq!(free_part(&candidate, &far, 10.0), Some(candidate));
    // A patch over 130–145 leaves 146–160 free: 14 mm about 153.
    let below = [patch(0.0, 137.5, 15.0), patch(0.0, 100.0, 20.0)];
    let part = free_part(&candidate, &below, 10.0).unwrap();
    assert!((part.y_mm - 153.0).abs() < 1e-9, "{part:?}");
    assert!((part.h_mm - 14.0).abs() < 1e-9, "{part:?}");
    assert_eq!((part.x_mm, part.w_mm, part.theta_deg), (3.0, 2.0, 10.0));
    // Two patches, over 140–146 and 155–170: 147–154 (7 mm) is the longest.
    let both = [patch(0.0, 143.0, 6.0), patch(0.0, 162.5, 15.0)];
    assert_eq!(free_part(&candidate, &both, 10.0), None);
    let part = free_part(&candidate, &both, 5.0).unwrap();
    assert!((part.y_mm - 150.5).abs() < 1e-9 && (part.h_mm - 7.0).abs() < 1e-9);
}

#[test]
fn added_patches_are_turned_into_the_designs_frame() {
    let circumference = TAU * 3.18;
    let design = [patch(5.0, 50.0, 20.0), patch(7.0, 150.0, 20.0)];
    let ksa = [
        patch(1.0, 52.0, 18.0),
        patch(3.0, 149.0, 22.0),
        patch(2.0, 250.0, 20.0),
    ];
    let offset = frame_offset(&design, &ksa, circumference);
    assert!((offset - 4.0).abs() < 1e-9, "{offset}");
    // Across the seam: 19 and 1 are 2 mm apart on a 19.98 mm circumference.
    let seam = frame_offset(
        &[patch(0.5, 50.0, 20.0)],
        &[patch(19.0, 50.0, 20.0)],
        circumference,
    );
    assert!((seam - (0.5 - 19.0 + circumference)).abs() < 1e-9, "{seam}");
    assert_eq!(frame_offset(&[], &ksa, circumference), 0.0);
}

/// An arc of radius 300 mm (κ = 0.0033 mm⁻¹, under even 0.4 of KSA's 0.01)
/// is curved, so the finer tolerance drops to half its curvature and the
/// design gets patches along it; a straight line with 0.3 mm of noise is
/// not curved and keeps 0.4 of KSA's tolerance.
#[test]
fn a_very_gentle_arc_gets_patches_and_a_noisy_line_does_not_lower_the_tolerance() {
    let arc = arc(300.0, 100.0);
    let tolerance = finer_tolerance(&arc, &curvature(&arc), 0.01);
    assert!(
        (tolerance - GENTLE / 300.0).abs() < 0.05 * GENTLE / 300.0,
        "{tolerance}"
    );
    let empty = balloon(150.0, vec![]);
    let finer = with_gentle_bends(&empty, &arc, 0.01, &trains(), 10.0).unwrap();
    assert!(finer.patches.len() >= 4, "{:?}", finer.patches);
    let line = Preset::from_name("line", serde_json::json!({"length_mm": 300}))
        .unwrap()
        .curve(Some(400))
        .unwrap()
        .with_noise(0.3 / 300.0, 3)
        .unwrap();
    assert_eq!(
        finer_tolerance(&line, &curvature(&line), 0.01),
        FINER * 0.01
    );
}

fn sized(y: f64, h: f64, w: f64) -> Patch {
    Patch {
        h_mm: h,
        w_mm: w,
        ..patch(0.0, y, h)
    }
}

/// Of the longest run of patches at both their smallest height and width,
/// the middle one goes and the run's others are spaced evenly between its
/// ends; patches off the run keep their places. A patch at only one of the
/// two limits is not at its weakest, and a design without any is not thinned.
#[test]
fn thinning_takes_the_middle_of_the_weakest_run_and_respaces_it() {
    let bounds = VariableBounds::default();
    let (h, w) = (bounds.h_min_mm, bounds.w_min_mm);
    // P1 wide (not weakest), P2–P5 weakest, unevenly spaced, P6 long (not
    // weakest), P7 weakest on its own.
    let design = balloon(
        300.0,
        vec![
            sized(5.0, 16.0, 3.0),
            sized(40.0, h, w),
            sized(80.0, h, w),
            sized(120.0, h, w),
            sized(150.0, h, w),
            sized(200.0, 20.0, w),
            sized(250.0, h, w),
        ],
    );
    let (thinned, removed) = thinned(&design, &bounds).unwrap();
    assert_eq!(removed, 4, "the middle of P2–P5");
    let y: Vec<f64> = thinned.patches.iter().map(|p| p.y_mm).collect();
    let expected = [5.0, 40.0, 95.0, 150.0, 200.0, 250.0];
    assert_eq!(y.len(), expected.len());
    for (got, want) in y.iter().zip(expected) {
        assert!((got - want).abs() < 1e-9, "{y:?}");
    }
    // At its smallest height but wider than the narrowest: not weakest.
    let strong = balloon(300.0, vec![sized(40.0, h, 2.0), sized(80.0, 20.0, w)]);
    assert!(super::thinned(&strong, &bounds).is_none());
    // A lone weakest patch goes, and nothing moves.
    let lone = balloon(300.0, vec![sized(40.0, 20.0, 2.0), sized(80.0, h, w)]);
    let (rest, removed) = super::thinned(&lone, &bounds).unwrap();
    assert_eq!(removed, 2);
    assert_eq!(rest.patches, vec![sized(40.0, 20.0, 2.0)]);
    // The last patch stays, weakest or not.
    let single = balloon(300.0, vec![sized(80.0, h, w)]);
    assert!(super::thinned(&single, &bounds).is_none());
}

/// Two or more weakest patches next to each other along the tube make a
/// design overfull, in whatever order they are listed; one alone, or two
/// with a stronger patch between them, do not.
#[test]
fn a_run_of_weakest_patches_is_overfull() {
    let bounds = VariableBounds::default();
    let (h, w) = (bounds.h_min_mm, bounds.w_min_mm);
    let listed_out_of_order = balloon(
        300.0,
        vec![sized(120.0, h, w), sized(5.0, 16.0, 3.0), sized(80.0, h, w)],
    );
    assert!(super::overfull(&listed_out_of_order, &bounds));
    let apart = balloon(
        300.0,
        vec![sized(40.0, h, w), sized(80.0, 20.0, w), sized(120.0, h, w)],
    );
    assert!(!super::overfull(&apart, &bounds));
    let lone = balloon(300.0, vec![sized(40.0, 20.0, 2.0), sized(80.0, h, w)]);
    assert!(!super::overfull(&lone, &bounds));
}
