//! Calibration over HTTP: a calibration job fits the material to a bare
//! balloon's inflation (simulated by the server from a known material),
//! saves it as a balloon profile, and a design job made of the profile
//! carries the calibrated material; profiles are each key's own, and every
//! refusal names its field.

use std::time::Duration;

use reqwest::Method;
use serde_json::{Value, json};

use crate::support::*;

/// The truth: a 100 mm balloon of Arruda–Boyce latex stiffer than the
/// reference's (μ 0.34 MPa for 0.317).
const TRUE_MU: f64 = 0.34;

fn balloon(mu_mpa: f64) -> Value {
    json!({"length_mm": 100, "material": {"model": "arruda_boyce", "mu_mpa": mu_mpa, "lambda_m": 2.3}})
}

/// The true balloon's diameter across the middle (mid-wall) at
/// `pressure_kpa`, by the server's own forward model (`POST /v1/simulate`:
/// the hoop stretch there times the uninflated radius, 3.18 mm).
async fn measured_diameter(api: &Api, pressure_kpa: f64) -> f64 {
    let design = json!({"balloon": balloon(TRUE_MU), "pressure_kpa": pressure_kpa, "patches": []});
    let response = api.post("/v1/simulate", &json!({"design": design})).await;
    assert_eq!(response.status(), 200);
    let report: Value = response.json().await.unwrap();
    2.0 * 3.18 * report["hoop_stretch_mid"].as_f64().unwrap()
}

async fn put_profile(api: &Api, name: &str, body: &Value) -> reqwest::Response {
    let path = format!("/v1/balloons/{name}");
    api.request(Method::PUT, &path)
        .json(body)
        .send()
        .await
        .unwrap()
}

async fn delete(api: &Api, path: &str) -> reqwest::Response {
    api.request(Method::DELETE, path).send().await.unwrap()
}

#[tokio::test(flavor = "multi_thread")]
async fn a_calibration_saves_a_profile_that_a_design_job_is_made_of() {
    let server = Server::start();
    let api = server.api();
    let inflation = measured_inflation(&api).await;
    let request = json!({
        "balloon": balloon(0.317),
        "inflation": inflation,
        "fit": ["modulus"],
        "save_as": "batch-7",
    });
    let response = api.post("/v1/calibrations", &request).await;
    assert_eq!(response.status(), 202);
    let job: Value = response.json().await.unwrap();
    assert_schema("Job", &job);
    assert_eq!(job["kind"], "calibrate");
    let id = job["id"].as_str().unwrap().to_string();
    let done = api
        .wait_for(&id, &["succeeded", "failed"], Duration::from_secs(300))
        .await;
    assert_eq!(done["status"], "succeeded", "{done}");
    assert_schema("Job", &done);
    assert_eq!(done["fit"], json!(["modulus"]));
    assert_eq!(done["progress"]["stage"], "calibrate");
    assert_eq!(done["request"]["save_as"], "batch-7");

    // The answer: the true modulus (the model's own data, no noise).
    let result: Value = api
        .get(&format!("/v1/jobs/{id}/result"))
        .await
        .json()
        .await
        .unwrap();
    assert_schema("Calibration", &result);
    let mu = result["parameters"][0]["value"].as_f64().unwrap();
    assert!((mu / TRUE_MU - 1.0).abs() < 0.01, "{result}");
    let [lo, hi] = [0, 1].map(|i| result["parameters"][0]["interval95"][i].as_f64().unwrap());
    assert!(lo <= mu && mu <= hi, "{result}");
    assert_eq!(result["material"]["mu_mpa"].as_f64(), Some(mu));
    let options: Value = api
        .get(&format!("/v1/jobs/{id}/files/options.json"))
        .await
        .json()
        .await
        .unwrap();
    assert_eq!(options["balloon"]["material"]["mu_mpa"].as_f64(), Some(mu));
    assert_eq!(options["balloon"]["length_mm"].as_f64(), Some(100.0));
    let no_design = api.get(&format!("/v1/jobs/{id}/files/design.json")).await;
    assert_problem(no_design, 404, None).await;
    let compare = json!({"measured": {"preset": "arc"}});
    let refused = api.post(&format!("/v1/jobs/{id}/compare"), &compare).await;
    assert_problem(refused, 409, None).await;

    // The saved profile, and a design job made of it.
    let profile: Value = api.get("/v1/balloons/batch-7").await.json().await.unwrap();
    assert_schema("BalloonProfile", &profile);
    assert_eq!(profile["source_job"], id.as_str());
    assert_eq!(profile["balloon"], options["balloon"]);
    let list: Value = api.get("/v1/balloons").await.json().await.unwrap();
    assert_schema("BalloonProfileList", &list);
    assert_eq!(list["balloons"][0]["name"], "batch-7");
    let mut design_job = quick_job(8);
    design_job["balloon_profile"] = json!("batch-7");
    let design_id = api.submit(&design_job).await;
    // The profile changed after submission changes nothing of the job.
    let replaced = put_profile(&api, "batch-7", &json!({"balloon": balloon(0.5)})).await;
    assert_eq!(replaced.status(), 200);
    let design = api
        .wait_for(
            &design_id,
            &["succeeded", "failed"],
            Duration::from_secs(300),
        )
        .await;
    assert_eq!(design["status"], "succeeded", "{design}");
    let report: Value = (api.get(&format!("/v1/jobs/{design_id}/result")).await)
        .json()
        .await
        .unwrap();
    assert_eq!(
        report["design"]["balloon"]["material"]["mu_mpa"].as_f64(),
        Some(mu)
    );

    // Deleted: gone, and a job naming it is refused by the field.
    assert_eq!(delete(&api, "/v1/balloons/batch-7").await.status(), 204);
    assert_problem(api.get("/v1/balloons/batch-7").await, 404, None).await;
    assert_problem(delete(&api, "/v1/balloons/batch-7").await, 404, None).await;
    let refused = api.post("/v1/jobs", &design_job).await;
    assert_problem(refused, 422, Some("balloon_profile")).await;
}

/// The diameter at 18 and 22 kPa.
async fn measured_inflation(api: &Api) -> Vec<Value> {
    let mut inflation = Vec::new();
    for pressure_kpa in [18.0, 22.0] {
        let diameter_mm = measured_diameter(api, pressure_kpa).await;
        inflation.push(json!({"pressure_kpa": pressure_kpa, "diameter_mm": diameter_mm}));
    }
    inflation
}

#[tokio::test(flavor = "multi_thread")]
async fn a_calibration_is_refused_by_the_field_and_profiles_are_each_keys_own() {
    let server = Server::with(Options {
        keys: Some("key-alice, key-bob"),
        ..Options::default()
    });
    let (alice, bob) = (server.as_key("key-alice"), server.as_key("key-bob"));
    let cases = [
        (
            json!({"inflation": [{"pressure_kpa": 18, "length_mm": 300}, {"pressure_kpa": 22, "length_mm": 200}]}),
            "inflation[1]",
        ),
        (
            json!({"inflation": [{"pressure_kpa": 0, "length_mm": 300}]}),
            "inflation[0]",
        ),
        (json!({}), "inflation"),
        (
            json!({"pressure_volume": [{"pressure_kpa": 20, "volume_ml": 30}]}),
            "pressure_volume[0]",
        ),
        (
            json!({"inflation": [{"pressure_kpa": 20, "length_mm": 300}], "fit": ["patch_modulus"]}),
            "fit",
        ),
        (
            json!({"inflation": [{"pressure_kpa": 20, "length_mm": 300}], "fit": ["modulus", "lambda_m"]}),
            "fit",
        ),
        (
            json!({"inflation": [{"pressure_kpa": 20, "length_mm": 300}], "save_as": "../x"}),
            "save_as",
        ),
        (
            json!({"inflation": [{"pressure_kpa": 20, "length_mm": 300}], "balloon_profile": "none"}),
            "balloon_profile",
        ),
        (
            json!({"built": [{"job": "0190b8a0-0000-7000-8000-000000000000", "measured": {"preset": "arc"}}]}),
            "built[0].job",
        ),
        (
            json!({"built": [{"measured": {"preset": "arc"}}]}),
            "built[0]",
        ),
        (
            json!({"inflation": [{"pressure_kpa": 20, "length_mm": 300}], "fit": ["stiffness"]}),
            "fit[0]",
        ),
    ];
    for (body, field) in cases {
        let response = alice.post("/v1/calibrations", &body).await;
        let status = response.status().as_u16();
        let problem: Value = response.json().await.unwrap();
        assert!([400, 422].contains(&status), "{body}: {problem}");
        assert_eq!(problem["field"], field, "{body}: {problem}");
    }

    // A profile is its key's: another key neither sees it nor designs with it.
    let body = json!({"balloon": balloon(0.33)});
    assert_eq!(put_profile(&alice, "latex-a", &body).await.status(), 201);
    assert_problem(bob.get("/v1/balloons/latex-a").await, 404, None).await;
    let none: Value = bob.get("/v1/balloons").await.json().await.unwrap();
    assert_eq!(none["balloons"], json!([]));
    let mut job = quick_job(8);
    job["balloon_profile"] = json!("latex-a");
    assert_problem(
        bob.post("/v1/jobs", &job).await,
        422,
        Some("balloon_profile"),
    )
    .await;
    job["design"] = json!({"balloon": {"length_mm": 200}});
    let both = alice.post("/v1/jobs", &job).await;
    assert_problem(both, 422, Some("balloon_profile")).await;
    let both = json!({"balloon_profile": "latex-a", "balloon": balloon(0.3),
                      "inflation": [{"pressure_kpa": 20, "length_mm": 300}]});
    let refused = alice.post("/v1/calibrations", &both).await;
    assert_problem(refused, 422, Some("balloon_profile")).await;

    // A profile's own refusals.
    let thick = json!({"balloon": {"radius_mm": 3, "wall_mm": 4}});
    assert_problem(
        put_profile(&alice, "thick", &thick).await,
        422,
        Some("balloon.wall_mm"),
    )
    .await;
    assert_problem(put_profile(&alice, "-bad", &body).await, 422, Some("name")).await;
    let unknown = json!({"balloon": {}, "colour": "red"});
    let refused = put_profile(&alice, "latex-b", &unknown).await;
    assert!([400, 422].contains(&refused.status().as_u16()));
    assert_problem(alice.get("/v1/balloons/nothing-here").await, 404, None).await;
}
