//! `patchwork compare` end to end: a design's prediction and a "built"
//! balloon, both simulated by the real binary, one patch turned on the
//! built one; bad input refused in one line.

mod common;
use common::cli::{assert_one_line_error, json, patchwork, patchwork_with_stdin, temp_dir};

use serde_json::{Value, json};

/// A 120 mm balloon with patches at Y = 35, 60 and 85 mm; `turn` turns
/// P2 by that many degrees.
fn design(turn: f64) -> Value {
    let patch = |y: f64, theta: f64| json!({"x_mm": 0, "y_mm": y, "h_mm": 14, "w_mm": 1.5, "theta_deg": theta});
    json!({
        "balloon": {"length_mm": 120},
        "patches": [patch(35.0, 0.0), patch(60.0, turn), patch(85.0, 0.0)],
    })
}

/// design.json for `design(0)`: its design and its simulated centreline
/// (on a 1 mm mesh, to keep the test short), and the built balloon's
/// centreline with P2 turned by 20° (centreline.csv).
fn prediction_and_built(dir: &std::path::Path) -> (String, String) {
    let simulate = |design: &Value, out: &str| {
        let mut args = vec!["simulate", "-", "--json", "--mesh-mm", "1"];
        if !out.is_empty() {
            args.extend(["--out", out]);
        }
        json(&patchwork_with_stdin(&args, &design.to_string()))
    };
    let predicted = simulate(&design(0.0), "");
    let report = json!({"design": design(0.0), "centreline_mm": predicted["centreline_mm"]});
    let design_json = dir.join("design.json");
    std::fs::write(&design_json, report.to_string()).unwrap();
    let built = dir.join("built");
    simulate(&design(20.0), &built.to_string_lossy());
    (
        design_json.to_string_lossy().into(),
        built.join("centreline.csv").to_string_lossy().into(),
    )
}

#[test]
fn compare_finds_the_turned_patch_and_writes_its_files() {
    let scratch = temp_dir("compare");
    let (design_json, built) = prediction_and_built(scratch.path());
    let out = scratch.path().join("compare");
    let report = json(&patchwork(&[
        "compare",
        &design_json,
        &built,
        "--json",
        "--out",
        &out.to_string_lossy(),
    ]));
    assert_eq!(report["most_divergent_patch"], 2, "{:#}", report["patches"]);
    let patches = report["patches"].as_array().unwrap();
    let twist = |i: usize, which: &str| patches[i][which].as_f64().unwrap();
    // The turned patch twists the balloon; the others do not (straight
    // patches at Θ = 0 bend in a plane).
    assert!((twist(1, "measured_twist_deg") - twist(1, "predicted_twist_deg")).abs() > 10.0);
    assert!(
        report["against_prediction"]["shape_error_mm"]
            .as_f64()
            .unwrap()
            > 0.5
    );
    assert_eq!(report["measured"]["reversed"], false);
    assert!(out.join("compare.svg").exists());
    let written: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("compare.json")).unwrap()).unwrap();
    assert_eq!(written, report);

    // The prediction against itself, given tip to base; as the target too
    // (a target runs base to tip: the design's base is its first point).
    let mut lines: Vec<String> = report_points(&design_json);
    let forward = scratch.path().join("forward.csv");
    std::fs::write(&forward, lines.join("\n")).unwrap();
    lines.reverse();
    let reversed = scratch.path().join("reversed.csv");
    std::fs::write(&reversed, lines.join("\n")).unwrap();
    let same = json(&patchwork(&[
        "compare",
        &design_json,
        &reversed.to_string_lossy(),
        "--target",
        &forward.to_string_lossy(),
        "--json",
    ]));
    assert_eq!(same["measured"]["reversed"], true);
    assert!(
        same["against_prediction"]["shape_error_mm"]
            .as_f64()
            .unwrap()
            < 1e-6
    );
    assert!(same["against_target"]["shape_error_mm"].as_f64().unwrap() < 1e-6);

    let text = String::from_utf8(patchwork(&["compare", &design_json, &built]).stdout).unwrap();
    assert!(
        text.contains("vs predicted:") && text.contains("P2"),
        "{text}"
    );
    assert!(
        text.lines()
            .any(|l| l.starts_with("P2") && l.ends_with("diverges most")),
        "{text}"
    );
}

fn report_points(design_json: &str) -> Vec<String> {
    let report: Value =
        serde_json::from_str(&std::fs::read_to_string(design_json).unwrap()).unwrap();
    report["centreline_mm"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| format!("{},{},{}", p[0], p[1], p[2]))
        .collect()
}

#[test]
fn compare_refuses_bad_input_in_one_line() {
    let scratch = temp_dir("compare-bad");
    let dir = scratch.path();
    let centreline: Vec<Value> = (0..40).map(|i| json!([0.0, 0.0, 4.0 * i as f64])).collect();
    let report = json!({"design": design(0.0), "centreline_mm": centreline});
    let design_json = dir.join("design.json");
    std::fs::write(&design_json, report.to_string()).unwrap();
    let design_json = design_json.to_string_lossy().to_string();
    let straight = dir.join("straight.csv");
    let lines: Vec<String> = (0..50)
        .map(|i| format!("0,0,{}", 156.0 / 49.0 * i as f64))
        .collect();
    std::fs::write(&straight, lines.join("\n")).unwrap();
    let straight = straight.to_string_lossy().to_string();

    // Millimetres read as metres: 156 m against 156 mm.
    assert_one_line_error(
        &patchwork(&["compare", &design_json, &straight, "--units", "m"]),
        "are its units right",
    );
    // A plain design has no prediction.
    let plain = dir.join("plain.json");
    std::fs::write(&plain, design(0.0).to_string()).unwrap();
    assert_one_line_error(
        &patchwork(&["compare", &plain.to_string_lossy(), &straight]),
        "centreline_mm",
    );
    let two = dir.join("two.csv");
    std::fs::write(&two, "0,0,0\n0,0,1\n").unwrap();
    assert_one_line_error(
        &patchwork(&["compare", &design_json, &two.to_string_lossy()]),
        "at least 4",
    );
    assert_one_line_error(
        &patchwork(&["compare", &design_json, "missing.csv"]),
        "missing.csv",
    );
    // The straight measurement against a straight prediction: no error.
    let fine = json(&patchwork(&["compare", &design_json, &straight, "--json"]));
    assert!(
        fine["against_prediction"]["shape_error_mm"]
            .as_f64()
            .unwrap()
            < 0.1
    );
}

/// The built balloon scanned: `simulate --out` writes its inflated surface
/// as balloon.ply (a mesh, sampled over its faces), and `compare` takes the
/// centreline out of it; a scan that is not a tube is refused in one line.
#[test]
fn compare_reads_a_scan_of_the_built_balloon() {
    let scratch = temp_dir("compare-scan");
    let (design_json, built) = prediction_and_built(scratch.path());
    let scan = std::path::Path::new(&built).with_file_name("balloon.ply");
    let out = scratch.path().join("scan-compare");
    let report = json(&patchwork(&[
        "compare",
        &design_json,
        &scan.to_string_lossy(),
        "--json",
        "--out",
        &out.to_string_lossy(),
    ]));
    assert_eq!(report["most_divergent_patch"], 2, "{:#}", report["patches"]);
    assert_eq!(report["scan"]["points"], 300_000);
    assert!(out.join("scan_centreline.csv").exists());
    // The same balloon's centreline as a CSV and as a scan agree.
    let from_points = json(&patchwork(&["compare", &design_json, &built, "--json"]));
    let shape = |r: &Value| {
        r["against_prediction"]["shape_error_percent"]
            .as_f64()
            .unwrap()
    };
    assert!(
        (shape(&report) - shape(&from_points)).abs() < 0.2,
        "{} {}",
        shape(&report),
        shape(&from_points)
    );

    let ball = scratch.path().join("ball.xyz");
    let points: String = (0..2000)
        .map(|i| {
            let (a, b) = (
                i as f64 * 2.399963,
                (1.0 - 2.0 * (i as f64 + 0.5) / 2000.0).acos(),
            );
            format!(
                "{} {} {}\n",
                20.0 * b.sin() * a.cos(),
                20.0 * b.sin() * a.sin(),
                20.0 * b.cos()
            )
        })
        .collect();
    std::fs::write(&ball, points).unwrap();
    assert_one_line_error(
        &patchwork(&["compare", &design_json, &ball.to_string_lossy()]),
        "does not look like a tube",
    );
    let few = scratch.path().join("few.xyz");
    std::fs::write(&few, "0 0 0\n1 0 0\n0 1 0\n0 0 1\n").unwrap();
    assert_one_line_error(
        &patchwork(&["compare", &design_json, &few.to_string_lossy()]),
        "at least 1000",
    );
}
