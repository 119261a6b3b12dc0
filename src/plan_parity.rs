//! The CLI and the API resolve a design run through the same resolver: the
//! same settings given as flags and as a job request make the same plan.

use clap::Parser;
use patchwork_core::inverse::Plan;

use crate::cli::design_cmd::DesignArgs;
use crate::service::request::JobRequest;

#[derive(Parser)]
struct Command {
    #[command(flatten)]
    args: DesignArgs,
}

fn from_cli(flags: &[&str]) -> Plan {
    let argv = [
        "patchwork",
        "curve.csv",
        "--out",
        "unused",
        "--threads",
        "1",
    ];
    let command = Command::try_parse_from(argv.iter().chain(flags)).expect("flags parse");
    command.args.plan().expect("the CLI resolves a plan")
}

fn from_api(job: serde_json::Value) -> Plan {
    let mut job = job;
    job["curve"] = serde_json::json!({"preset": "arc"});
    let request: JobRequest = serde_json::from_value(job).expect("the request parses");
    match request.spec(None) {
        Ok(design) => design.plan().clone(),
        Err(error) => panic!("the API resolves no plan: {error}"),
    }
}

#[test]
fn the_same_settings_make_the_same_plan_through_the_cli_and_the_api() {
    let scratch = tempfile::tempdir().unwrap();
    let options = scratch.path().join("options.json");
    std::fs::write(&options, r#"{"pressure_kpa": 25}"#).unwrap();
    let options = options.to_str().unwrap();
    let cases: [(&[&str], serde_json::Value); 4] = [
        (&[], serde_json::json!({})),
        (
            &["--fidelity", "draft", "--seed", "7", "--budget", "40"],
            serde_json::json!({"options": {"fidelity": "draft", "seed": 7, "budget": 40}}),
        ),
        (
            &[
                "--fidelity",
                "fine",
                "--tuning",
                r#"{"search_patience": 0, "refine_budget": 90, "correction": false,
                    "polish_budget": 30, "initial_step": 0.1, "start": "even",
                    "objective": {"shape_weight": 3, "squared": true}}"#,
                "--fix-length",
                "--bounds",
                r#"{"w_min_mm": 0.5, "h_max_mm": 40}"#,
            ],
            serde_json::json!({
                "options": {"fidelity": "fine", "fix_length": true},
                "tuning": {
                    "search_patience": 0, "refine_budget": 90, "correction": false,
                    "polish_budget": 30, "initial_step": 0.1, "start": "even",
                    "objective": {"shape_weight": 3, "squared": true}
                },
                "bounds": {"w_min_mm": 0.5, "h_max_mm": 40}
            }),
        ),
        (
            &["--options", options],
            serde_json::json!({"design": {"pressure_kpa": 25}}),
        ),
    ];
    for (flags, job) in cases {
        let (cli, api) = (from_cli(flags), from_api(job.clone()));
        assert_eq!(cli, api, "{flags:?} against {job}");
    }
    // Plans do tell settings apart: a different patience is another plan.
    assert_ne!(
        from_cli(&["--tuning", r#"{"search_patience": 10}"#]),
        from_api(serde_json::json!({"tuning": {"search_patience": 20}}))
    );
}
