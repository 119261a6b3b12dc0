//! `patchwork spread` end to end: a short three-patch balloon whose long
//! base patch turns everything after it is named as what matters most; the
//! JSON adds up; bad tolerances are refused in one line.

mod common;
use common::cli::{assert_one_line_error, json, patchwork_with_stdin};

/// 120 mm of reference balloon: a long, wide patch near the base, two
/// small ones near the tip.
const DESIGN: &str = r#"{"balloon": {"length_mm": 120}, "patches": [
    {"x_mm": 0, "y_mm": 30, "h_mm": 30, "w_mm": 3, "theta_deg": 0},
    {"x_mm": 0, "y_mm": 85, "h_mm": 6, "w_mm": 1, "theta_deg": 0},
    {"x_mm": 0, "y_mm": 105, "h_mm": 6, "w_mm": 1, "theta_deg": 0}]}"#;

const PATCHES_ONLY: &str = r#"{"pressure_kpa": 0, "wall_percent": 0, "modulus_percent": 0}"#;

#[test]
fn spread_names_what_matters_most_and_refuses_bad_tolerances() {
    let text = patchwork_with_stdin(&["spread", "-", "--tolerances", PATCHES_ONLY], DESIGN);
    let stdout = String::from_utf8_lossy(&text.stdout);
    assert!(
        text.status.success(),
        "{}",
        String::from_utf8_lossy(&text.stderr)
    );
    assert!(stdout.contains("matters most: P1 "), "{stdout}");
    // The count printed: the nominal design on the verification model and
    // again on the patches' model, one linearisation of all fifteen
    // sources there, and each large source solved in full both ways.
    let same = json(&patchwork_with_stdin(
        &["spread", "-", "--json", "--tolerances", PATCHES_ONLY],
        DESIGN,
    ));
    let solved = same["contributors"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|c| c["estimate"] == "both_ways")
        .count();
    assert!((1..15).contains(&solved), "{same}");
    assert_eq!(
        same["solves"].as_u64(),
        Some(3 + 2 * solved as u64),
        "{same}"
    );
    assert!(
        stdout.contains(&format!("{} FE solves", 3 + 2 * solved)),
        "{stdout}"
    );
    // With every source: the balloon's three join the patches' fifteen.
    let all = json(&patchwork_with_stdin(
        &["spread", "-", "--json", "--top", "5"],
        DESIGN,
    ));
    let contributors = all["contributors"].as_array().unwrap();
    assert_eq!(contributors.len(), 18);
    // In quadrature, each source's mean move taken out and their sum put
    // back (design.json's `mean_shift_mm`).
    let f = |v: &serde_json::Value, key: &str| v[key].as_f64().unwrap();
    let scatter: f64 = contributors
        .iter()
        .map(|c| f(c, "rms_mm").powi(2) - f(c, "shift_mm").powi(2))
        .sum();
    let together = (scatter + f(&all, "mean_shift_mm").powi(2)).sqrt();
    assert!((f(&all, "rms_mm") - together).abs() < 1e-9, "{all}");
    assert!(f(&all, "mean_shift_mm") > 0.0, "{all}");
    assert!(contributors.iter().any(|c| c["source"] == "pressure"));
    assert!(
        all.get("expected_shape_error_percent").is_none(),
        "no target: {all}"
    );

    // Against a design.json's target: the expected error is the nominal's
    // and the spread's in quadrature.
    let target: Vec<[f64; 3]> = (0..30).map(|i| [0.0, 0.0, 5.0 * i as f64]).collect();
    let report = serde_json::json!({
        "design": serde_json::from_str::<serde_json::Value>(DESIGN).unwrap(),
        "target_mm": target,
    });
    let against = json(&patchwork_with_stdin(
        &["spread", "-", "--json", "--tolerances", PATCHES_ONLY],
        &report.to_string(),
    ));
    let (nominal, expected, spread) = (
        against["nominal_shape_error_percent"].as_f64().unwrap(),
        against["expected_shape_error_percent"].as_f64().unwrap(),
        against["rms_percent"].as_f64().unwrap(),
    );
    assert!(
        nominal > 0.0 && (expected - nominal.hypot(spread)).abs() < 1e-9,
        "{against}"
    );

    // The Monte-Carlo check on request: every source drawn at once, the
    // samples solved, the verdict printed.
    let wall = r#"{"placement_mm": 0, "angle_deg": 0, "size_mm": 0, "pressure_kpa": 0, "modulus_percent": 0}"#;
    let checked = patchwork_with_stdin(
        &[
            "spread",
            "-",
            "--tolerances",
            wall,
            "--monte-carlo",
            "12",
            "--seed",
            "3",
        ],
        DESIGN,
    );
    let stdout = String::from_utf8_lossy(&checked.stdout);
    assert!(checked.status.success(), "{stdout}");
    assert!(
        stdout.contains("Monte-Carlo:  12 samples (seed 3): "),
        "{stdout}"
    );
    assert!(stdout.contains("× the linear estimate"), "{stdout}");
    // The nominal, the linearisation, the one source solved both ways, 12
    // samples (no patch source: no patches' model); its mean move printed.
    assert!(stdout.contains("16 FE solves"), "{stdout}");
    assert!(stdout.contains("on average:   "), "{stdout}");
    assert_one_line_error(
        &patchwork_with_stdin(&["spread", "-", "--monte-carlo", "1"], DESIGN),
        "--monte-carlo",
    );

    let negative = r#"{"angle_deg": -1}"#;
    let refused = patchwork_with_stdin(&["spread", "-", "--tolerances", negative], DESIGN);
    assert_one_line_error(&refused, "angle_deg");
    let unknown = r#"{"angle": 1}"#;
    let refused = patchwork_with_stdin(&["spread", "-", "--tolerances", unknown], DESIGN);
    assert_one_line_error(&refused, "angle");
}
