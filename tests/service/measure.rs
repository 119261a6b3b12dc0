//! A built balloon measured against its design over HTTP: the job's own
//! route and the stateless one, answers held to openapi's `Comparison`,
//! refusals naming the field.

use std::time::Duration;

use serde_json::{Value, json};

use crate::support::*;

/// The job's design.json, once it has succeeded.
async fn finished_result(api: &Api, id: &str) -> Value {
    let job = api
        .wait_for(id, &["succeeded"], Duration::from_secs(120))
        .await;
    assert_eq!(job["status"], "succeeded");
    api.get(&format!("/v1/jobs/{id}/result"))
        .await
        .json()
        .await
        .unwrap()
}

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
    let result = finished_result(&api, &id).await;
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

/// The inflated surface the job's design predicts (`POST /v1/simulate`
/// with its surface) as an ASCII PLY mesh: the rings' quadrilaterals and
/// the pole's fan, as openapi describes `surface`.
pub async fn surface_ply(api: &Api, design: &Value) -> String {
    let sim: Value = api
        .post("/v1/simulate", &json!({"design": design, "surface": true}))
        .await
        .json()
        .await
        .unwrap();
    let surface = &sim["surface"];
    let around = surface["around"].as_u64().unwrap() as usize;
    let positions = surface["positions_mm"].as_array().unwrap();
    let rings = (positions.len() - 1) / around;
    let pole = positions.len() - 1;
    let mut faces = Vec::new();
    for k in 0..rings - 1 {
        for j in 0..around {
            let (a, b) = (k * around + j, k * around + (j + 1) % around);
            faces.push(format!("4 {a} {b} {} {}", b + around, a + around));
        }
    }
    let last = (rings - 1) * around;
    for j in 0..around {
        faces.push(format!("3 {} {} {pole}", last + j, last + (j + 1) % around));
    }
    let vertices: String = positions
        .iter()
        .map(|p| format!("{} {} {}\n", p[0], p[1], p[2]))
        .collect();
    format!(
        "ply\nformat ascii 1.0\nelement vertex {}\nproperty double x\nproperty double y\nproperty double z\n\
         element face {}\nproperty list uchar int vertex_indices\nend_header\n{vertices}{}\n",
        positions.len(),
        faces.len(),
        faces.join("\n")
    )
}

/// A scan of the balloon built from a job's design, uploaded as the file
/// itself: larger than the JSON body limit, within the scan limit; the
/// query and the file refused naming what is wrong; past the scan limit a
/// 413.
#[tokio::test(flavor = "multi_thread")]
async fn a_scan_of_the_built_balloon_is_compared_with_its_jobs_design() {
    let server = Server::with(Options {
        config: Some("body_limit_bytes = 100000\nscan_limit_bytes = 4000000\n"),
        ..Options::default()
    });
    let api = server.api();
    let id = api.submit(&quick_job(20)).await;
    let result = finished_result(&api, &id).await;
    let ply = surface_ply(&api, &result["design"]).await;
    assert!(ply.len() > 100_000, "{} bytes", ply.len());
    let upload = |query: &str, body: Vec<u8>| {
        api.request(
            reqwest::Method::POST,
            &format!("/v1/jobs/{id}/compare/scan{query}"),
        )
        .header("content-type", "application/octet-stream")
        .body(body)
        .send()
    };
    let response = upload("?format=ply", ply.clone().into_bytes())
        .await
        .unwrap();
    assert_eq!(response.status(), 200);
    let comparison: Value = response.json().await.unwrap();
    assert_schema("Comparison", &comparison);
    // The balloon built as predicted (simulated again on the route's
    // mesh): its ends, the neck at the clamp and where the cap begins,
    // are placed to about a millimetre on this 63 mm arc.
    let shape = comparison["against_prediction"]["shape_error_mm"]
        .as_f64()
        .unwrap();
    let length = comparison["length_difference_mm"].as_f64().unwrap();
    println!("scan against prediction: {shape} mm, length {length:+} mm");
    assert!(shape < 0.6 && length.abs() < 2.0, "{shape} mm, {length} mm");
    let radius = comparison["radius"]["difference_percent"].as_f64().unwrap();
    assert!(radius.abs() < 3.0, "{radius} %");
    assert!(comparison["scan"]["points"].as_u64().unwrap() >= 300_000);

    for (query, field) in [
        ("", "format"),
        ("?format=dwg", "format"),
        ("?format=ply&units=furlong", "units"),
        ("?format=ply&colour=red", "colour"),
    ] {
        let response = upload(query, ply.clone().into_bytes()).await.unwrap();
        assert_problem(response, 422, Some(field)).await;
    }
    let response = upload("?format=ply", b"not a scan".to_vec()).await.unwrap();
    assert_problem(response, 422, Some("scan")).await;
    let response = upload("?format=xyz", vec![b'1'; 5_000_000]).await.unwrap();
    assert_eq!(response.status(), 413);
}
