//! A built balloon measured against its design over HTTP: the job's own
//! route and the stateless one, answers held to openapi's `Comparison`,
//! refusals naming the field.

use std::time::Duration;

use serde_json::{Value, json};

use crate::support::*;

#[tokio::test(flavor = "multi_thread")]
async fn a_measured_centreline_is_compared_with_its_jobs_design() {
    let server = Server::start();
    let api = server.api();
    let id = api.submit(&quick_job(20)).await;
    // Not yet done: no design to compare with.
    let early = api
        .post(
            &format!("/v1/jobs/{id}/compare"),
            &json!({"measured": {"preset": "arc"}}),
        )
        .await;
    assert!([200, 409].contains(&early.status().as_u16()));
    let job = api
        .wait_for(&id, &["succeeded"], Duration::from_secs(120))
        .await;
    assert_eq!(job["status"], "succeeded");
    let result: Value = api
        .get(&format!("/v1/jobs/{id}/result"))
        .await
        .json()
        .await
        .unwrap();
    assert!(!result["target_mm"].as_array().unwrap().is_empty());

    // The balloon built exactly as predicted, its points given tip to base.
    let mut points = result["centreline_mm"].as_array().unwrap().clone();
    points.reverse();
    let body = json!({"measured": {"points": points}});
    let response = api.post(&format!("/v1/jobs/{id}/compare"), &body).await;
    assert_eq!(response.status(), 200);
    let comparison: Value = response.json().await.unwrap();
    assert_schema("Comparison", &comparison);
    assert_eq!(comparison["measured"]["reversed"], true);
    assert!(
        comparison["against_prediction"]["shape_error_mm"]
            .as_f64()
            .unwrap()
            < 1e-6
    );
    // The target is the job's curve, as given: the prediction's own miss.
    let own = result["as_given"]["shape_error_mm"].as_f64().unwrap();
    let against_target = comparison["against_target"]["shape_error_mm"]
        .as_f64()
        .unwrap();
    assert!(
        (against_target - own).abs() < 1e-6 * own.max(1.0),
        "{against_target} {own}"
    );
    assert_eq!(
        comparison["patches"].as_array().unwrap().len(),
        result["design"]["patches"].as_array().unwrap().len()
    );

    // The same through the stateless route, with the design.json in the body.
    let stateless = json!({"design": result, "measured": {"points": points}});
    let response = api.post("/v1/compare", &stateless).await;
    assert_eq!(response.status(), 200);
    let again: Value = response.json().await.unwrap();
    assert_eq!(again, comparison);

    // Refusals name the field.
    let metres = json!({"measured": {"points": points}, "units": "m"});
    let problem = assert_problem(
        api.post(&format!("/v1/jobs/{id}/compare"), &metres).await,
        422,
        Some("measured"),
    )
    .await;
    assert!(
        problem["detail"].as_str().unwrap().contains("units"),
        "{problem}"
    );
    let two = json!({"measured": {"points": [[0, 0, 0], [0, 0, 1]]}});
    assert_problem(
        api.post(&format!("/v1/jobs/{id}/compare"), &two).await,
        422,
        Some("measured.points"),
    )
    .await;
    let plain = json!({"design": result["design"], "measured": {"points": points}});
    assert_problem(api.post("/v1/compare", &plain).await, 422, Some("design")).await;
    let nothing = json!({"measured": {}});
    assert_problem(
        api.post(&format!("/v1/jobs/{id}/compare"), &nothing).await,
        422,
        Some("measured"),
    )
    .await;
    assert_problem(
        api.post("/v1/jobs/0123456789abcdef0123456789abcdef/compare", &body)
            .await,
        404,
        None,
    )
    .await;
}
