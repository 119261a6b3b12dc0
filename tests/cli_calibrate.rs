//! `patchwork calibrate` end to end: the reference latex's inflation (as
//! the FE model predicts it at four pressures) fitted back from another
//! material; the material file it writes; bad data refused in one line.

mod common;
use common::cli::{assert_one_line_error, json, patchwork, patchwork_with_stdin, temp_dir};

/// The reference balloon's length (clamp to tip) and diameter, as the model
/// gives them at 18–25 kPa (rounded as a lab would write them).
const REFERENCE: &str = "pressure_kpa,length_mm,diameter_mm\n\
                         18,823.8,25.47\n20,988.5,30.51\n22,1163.3,35.90\n25,1449.9,44.78\n";

const START: &str = r#"{"material": {"model": "arruda_boyce", "mu_mpa": 0.36, "lambda_m": 2.6}}"#;

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
        "pressure_kpa",
    );
    assert_one_line_error(&patchwork(&["calibrate", "missing.csv"]), "missing.csv");
}
