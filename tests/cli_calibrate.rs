//! `patchwork calibrate` and `patchwork redesign` end to end: the
//! reference latex's inflation (as the FE model predicts it at four
//! pressures) fitted back from another material; a built balloon (simulated
//! by the real binary with a softer patch) giving the patch's modulus back;
//! the options file written and taken by `design`; bad data refused in one
//! line.

mod common;
use common::cli::{assert_one_line_error, json, patchwork, patchwork_with_stdin, temp_dir};

use serde_json::{Value, json};

/// A 100 mm balloon of the reference latex (its radius and wall): its
/// length (clamp to tip) and diameter as the model gives them at 18–25 kPa
/// (rounded as a lab would write them).
const REFERENCE: &str = "pressure_kpa,length_mm,diameter_mm\n\
                         18,300.9,27.46\n20,360.9,32.85\n22,424.8,38.71\n25,528.8,48.26\n";

const START: &str =
    r#"{"length_mm": 100, "material": {"model": "arruda_boyce", "mu_mpa": 0.36, "lambda_m": 2.6}}"#;

#[test]
fn calibrate_recovers_the_reference_latex_and_writes_its_options() {
    let scratch = temp_dir("calibrate");
    let out = scratch.path().join("balloon.json");
    let report = json(&patchwork_with_stdin(
        &[
            "calibrate",
            "-",
            "--balloon",
            START,
            "--json",
            "--out",
            &out.to_string_lossy(),
        ],
        REFERENCE,
    ));
    let value = |i: usize| report["parameters"][i]["value"].as_f64().unwrap();
    assert!((value(0) / 0.317 - 1.0).abs() < 0.01, "{report:#}");
    assert!((value(1) / 2.3 - 1.0).abs() < 0.01, "{report:#}");
    assert!(report["rms_percent"].as_f64().unwrap() < 0.1);
    let written: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    assert_eq!(written["balloon"]["material"]["model"], "arruda_boyce");
    assert_eq!(
        written["balloon"]["material"]["mu_mpa"].as_f64(),
        Some(value(0))
    );
}

#[test]
fn calibrate_refuses_bad_data_in_one_line() {
    let run = |csv: &str, extra: &[&str]| {
        let mut args = vec!["calibrate", "-"];
        args.extend(extra);
        patchwork_with_stdin(&args, csv)
    };
    assert_one_line_error(&run("length_mm\n900\n", &[]), "pressure_kpa");
    assert_one_line_error(&run("pressure_kpa,length_mm\n20,abc\n", &[]), "line 2");
    assert_one_line_error(
        &run("pressure_kpa,length_mm\n20,988\n", &[]),
        "cannot determine 2 parameters",
    );
    assert_one_line_error(&run(REFERENCE, &["--fit", "stiffness"]), "--fit");
    assert_one_line_error(
        &run("pressure_kpa,length_mm\n-5,988\n", &["--fit", "modulus"]),
        "-: line 2: pressure_kpa",
    );
    assert_one_line_error(
        &run(
            "pressure_kpa,length_mm\n# a comment\n18,900\n20,700\n",
            &["--fit", "modulus"],
        ),
        "-: line 4: length_mm 700 at 20 kPa is below 900 at 18 kPa",
    );
    assert_one_line_error(&patchwork(&["calibrate", "missing.csv"]), "missing.csv");
}

/// An 80 mm balloon with two patches turned alike (part of a helix),
/// its patch material's μ given.
fn design(patch_mu: f64) -> Value {
    let patch = |y: f64| json!({"x_mm": 0, "y_mm": y, "h_mm": 20, "w_mm": 3, "theta_deg": 25});
    json!({
        "balloon": {"length_mm": 80},
        "patch": {"material": {"model": "neo_hookean", "mu_mpa": patch_mu, "bulk_ratio": 20.0}},
        "patches": [patch(25.0), patch(55.0)],
    })
}

/// design.json for the reference patch (its prediction, and its own
/// centreline as the target), and the centreline of the balloon built
/// with a patch of μ = 0.9 MPa instead of 1.3 (centreline.csv).
fn design_and_built(dir: &std::path::Path) -> (String, String) {
    let simulate = |design: &Value, out: &str| {
        let mut args = vec!["simulate", "-", "--json"];
        if !out.is_empty() {
            args.extend(["--out", out]);
        }
        json(&patchwork_with_stdin(&args, &design.to_string()))
    };
    let predicted = simulate(&design(1.3), "");
    let report = json!({
        "design": design(1.3),
        "centreline_mm": predicted["centreline_mm"],
        "target_mm": predicted["centreline_mm"],
    });
    let design_json = dir.join("design.json");
    std::fs::write(&design_json, report.to_string()).unwrap();
    let built = dir.join("built");
    simulate(&design(0.9), &built.to_string_lossy());
    (
        design_json.to_string_lossy().into(),
        built.join("centreline.csv").to_string_lossy().into(),
    )
}

#[test]
fn a_built_balloon_calibrates_the_patch_and_redesign_designs_on_it() {
    let scratch = temp_dir("calibrate-built");
    let (design_json, built) = design_and_built(scratch.path());
    let pair = format!("{design_json}={built}");
    let report = json(&patchwork(&[
        "calibrate",
        "--built",
        &pair,
        "--fit",
        "patch_modulus",
        "--json",
    ]));
    let patch = report["parameters"][0]["value"].as_f64().unwrap();
    assert!((patch / 0.9 - 1.0).abs() < 0.03, "{report:#}");
    let fit = &report["built"][0];
    assert!(
        fit["shape_error_percent"].as_f64().unwrap()
            < 0.2 * fit["shape_error_start_percent"].as_f64().unwrap(),
        "{fit:#}"
    );

    let out = scratch.path().join("again");
    let summary = patchwork(&[
        "redesign",
        &design_json,
        &built,
        "--out",
        &out.to_string_lossy(),
        "--fit",
        "patch_modulus",
        "--fidelity",
        "draft",
        "--budget",
        "10",
    ]);
    assert!(summary.status.success(), "{summary:?}");
    let text = String::from_utf8_lossy(&summary.stdout);
    for part in ["against its design", "calibrated to it", "the new design"] {
        assert!(text.contains(part), "{text}");
    }
    let read = |name: &str| -> Value {
        serde_json::from_str(&std::fs::read_to_string(out.join(name)).unwrap()).unwrap()
    };
    let calibrated = read("options.json")["patch"]["material"]["mu_mpa"]
        .as_f64()
        .unwrap();
    assert!((calibrated / 0.9 - 1.0).abs() < 0.03, "{calibrated}");
    let again = read("design/design.json");
    assert_eq!(
        again["design"]["patch"]["material"]["mu_mpa"].as_f64(),
        Some(calibrated)
    );
    assert!(out.join("compare/compare.json").exists());
    assert!(out.join("calibration.json").exists());
}

#[test]
fn built_and_volume_data_are_refused_in_one_line() {
    let scratch = temp_dir("calibrate-refused");
    let (design_json, built) = design_and_built(scratch.path());
    assert_one_line_error(
        &patchwork(&["calibrate", "--built", &design_json]),
        "DESIGN.json=MEASURED",
    );
    assert_one_line_error(
        &patchwork_with_stdin(&["calibrate", "-", "--fit", "patch_modulus"], REFERENCE),
        "patch_modulus needs a built design",
    );
    let one_point = scratch.path().join("pv.csv");
    std::fs::write(&one_point, "pressure_kpa,volume_ml\n20,880\n").unwrap();
    assert_one_line_error(
        &patchwork(&[
            "calibrate",
            "--volume",
            &one_point.to_string_lossy(),
            "--fit",
            "modulus",
        ]),
        "two points or more",
    );
    assert_one_line_error(&patchwork(&["calibrate"]), "nothing measured");
    // A design.json without its target cannot be designed again.
    let plain = scratch.path().join("plain.json");
    let mut report: Value =
        serde_json::from_str(&std::fs::read_to_string(&design_json).unwrap()).unwrap();
    report.as_object_mut().unwrap().remove("target_mm");
    std::fs::write(&plain, report.to_string()).unwrap();
    let out = scratch.path().join("never");
    assert_one_line_error(
        &patchwork(&[
            "redesign",
            &plain.to_string_lossy(),
            &built,
            "--out",
            &out.to_string_lossy(),
        ]),
        "no target_mm",
    );
    assert!(!out.exists(), "nothing is written for a refused redesign");
}
