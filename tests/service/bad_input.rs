//! Every kind of bad input gets a 4xx problem+json naming the field, and the
//! server keeps working (nothing is queued, nothing crashes).

use serde_json::{Value, json};

use crate::support::*;

async fn post_raw(api: &Api, path: &str, content_type: &str, body: Vec<u8>) -> reqwest::Response {
    api.request(reqwest::Method::POST, path)
        .header("content-type", content_type)
        .body(body)
        .send()
        .await
        .unwrap()
}

/// Sends only the head of a 20 MB POST with `Expect: 100-continue` over a raw
/// socket and returns everything the server writes before closing.
async fn oversized_head_only(server: &Server) -> String {
    use tokio::io::{AsyncReadExt, AsyncWriteExt};
    let address = server.base.trim_start_matches("http://").to_string();
    let mut socket = tokio::net::TcpStream::connect(&address).await.unwrap();
    let head = format!(
        "POST /v1/jobs HTTP/1.1\r\nHost: {address}\r\nContent-Type: application/json\r\n\
         Content-Length: 20000000\r\nExpect: 100-continue\r\n\r\n"
    );
    socket.write_all(head.as_bytes()).await.unwrap();
    let mut answer = Vec::new();
    tokio::time::timeout(
        std::time::Duration::from_secs(30),
        socket.read_to_end(&mut answer),
    )
    .await
    .expect("the server answers and closes without waiting for the body")
    .unwrap();
    String::from_utf8_lossy(&answer).into_owned()
}

#[tokio::test(flavor = "multi_thread")]
async fn bad_job_requests_are_4xx_problems_naming_the_field() {
    let server = Server::start();
    let api = server.api();
    let json_type = "application/json";

    // Malformed JSON, and a number JSON cannot hold (non-finite).
    assert_problem(
        post_raw(&api, "/v1/jobs", json_type, b"{\"curve\": ".to_vec()).await,
        400,
        None,
    )
    .await;
    let huge = br#"{"curve": {"points": [[0,0,0],[1,0,0],[2,1e999,0],[3,0,0]]}}"#.to_vec();
    assert_problem(post_raw(&api, "/v1/jobs", json_type, huge).await, 400, None).await;
    // Not JSON at all.
    assert_problem(
        post_raw(&api, "/v1/jobs", "text/plain", b"x,y,z".to_vec()).await,
        415,
        Some("Content-Type"),
    )
    .await;

    let cases: Vec<(Value, &str)> = vec![
        (json!({}), "curve"),
        (json!({"curve": {}}), "curve"),
        (
            json!({"curve": {"points": [[0, 0, 0], [1, 0, 0]]}}),
            "curve.points",
        ),
        (
            json!({"curve": {"points": [[0, 0, 0], [1, 0], [2, 0, 0], [3, 0, 0]]}}),
            "curve.points",
        ),
        (json!({"curve": {"points": "many"}}), "curve.points"),
        (
            json!({"curve": {"csv": "x,y,z\n0,0,0\n1,0,zero\n2,0,0\n3,0,0\n"}}),
            "curve.csv",
        ),
        (json!({"curve": {"preset": "lissajous"}}), "curve.preset"),
        (
            json!({"curve": {"preset": "helix", "params": {"radius_mm": -1}}}),
            "curve.params",
        ),
        (
            json!({"curve": {"preset": "helix", "params": {"colour": 1}}}),
            "curve.preset",
        ),
        (json!({"curve": {"preset": "arc", "csv": "0,0,0"}}), "curve"),
        (
            json!({"curve": {"preset": "arc"}, "units": "furlong"}),
            "units",
        ),
        (
            json!({"curve": {"preset": "arc"}, "colour": "red"}),
            "colour",
        ),
        (
            json!({"curve": {"preset": "arc"}, "options": {"budget": 0}}),
            "options.budget",
        ),
        (
            json!({"curve": {"preset": "arc"}, "tolerances": {"angle_deg": -1}}),
            "tolerances.angle_deg",
        ),
        (
            json!({"curve": {"preset": "arc"}, "tolerances": {"angle": 1}}),
            "tolerances",
        ),
        (
            json!({"curve": {"preset": "arc"}, "options": {"budget": 10_000_000}}),
            "options.budget",
        ),
        (
            json!({"curve": {"preset": "arc"}, "options": {"seed": 9_007_199_254_740_992_u64}}),
            "options.seed",
        ),
        (
            json!({"curve": {"preset": "arc"}, "options": {"smooth_mm": 1e9}}),
            "options.smooth_mm",
        ),
        (
            json!({"curve": {"preset": "arc"}, "tuning": {"refine_budget": 10_000_000}}),
            "tuning.refine_budget",
        ),
        (
            json!({"curve": {"preset": "arc"}, "tuning": {"refine_budget": -1}}),
            "tuning.refine_budget",
        ),
        (
            json!({"curve": {"preset": "arc"}, "tuning": {"search_patience": 10_000_000}}),
            "tuning.search_patience",
        ),
        (
            json!({"curve": {"preset": "arc"}, "tuning": {"correction": "yes"}}),
            "tuning.correction",
        ),
        (
            json!({"curve": {"preset": "arc"}, "tuning": {"monte_carlo": 1_000_000}}),
            "tuning.monte_carlo",
        ),
        (
            json!({"curve": {"preset": "arc"}, "tuning": {"robust": true, "spread": false}}),
            "tuning.robust",
        ),
        (
            json!({"curve": {"preset": "arc"}, "options": {"fidelity": "ultra"}}),
            "options.fidelity",
        ),
        (
            json!({"curve": {"preset": "arc"}, "options": {"seed": -1}}),
            "options.seed",
        ),
        (
            json!({"curve": {"preset": "arc"}, "bounds": {"h_min_mm": 40, "h_max_mm": 10}}),
            "bounds.h_min_mm",
        ),
        (
            json!({"curve": {"preset": "arc"}, "bounds": {"theta_limit_deg": 120}}),
            "bounds.theta_limit_deg",
        ),
        (
            json!({"curve": {"preset": "arc"}, "tuning": {"objective": {"shape_weight": -1}}}),
            "tuning.objective.shape_weight",
        ),
        (
            json!({"curve": {"preset": "arc"}, "tuning": {"objective": {"smooth_fraction": 2}}}),
            "tuning.objective.smooth_fraction",
        ),
        (
            json!({"curve": {"preset": "arc"}, "tuning": {"objective": {"weight": 1}}}),
            "tuning.objective.weight",
        ),
        (
            json!({"curve": {"preset": "arc"}, "tuning": {"initial_step": 0}}),
            "tuning.initial_step",
        ),
        (
            json!({"curve": {"preset": "arc"}, "tuning": {"start": "random"}}),
            "tuning.start",
        ),
        (
            json!({"curve": {"preset": "arc"}, "tuning": {"kappa_tol": 0}}),
            "tuning.kappa_tol",
        ),
        (
            json!({"curve": {"preset": "arc"}, "tuning": {"refine_tolerance": -0.1}}),
            "tuning.refine_tolerance",
        ),
        (
            json!({"curve": {"preset": "arc"}, "tuning": {"refine_tolerance": 80}}),
            "tuning.refine_tolerance",
        ),
        (
            json!({"curve": {"preset": "arc"}, "tuning": {"uniform_mesh_mm": 50}}),
            "tuning.uniform_mesh_mm",
        ),
        (
            json!({"curve": {"preset": "arc"}, "options": {"smooth_mm": -1}}),
            "options.smooth_mm",
        ),
        (
            json!({"curve": {"preset": "arc"}, "options": {"time_limit_s": 0}}),
            "options.time_limit_s",
        ),
        (
            json!({"curve": {"preset": "arc"}, "options": {"time_limit_s": 1e7}}),
            "options.time_limit_s",
        ),
        (
            json!({"curve": {"preset": "arc"}, "design": {"pressure_kpa": -5}}),
            "design.pressure_kpa",
        ),
        (
            json!({"curve": {"preset": "arc"}, "design": {"balloon": {"wall_mm": 10}}}),
            "design.balloon.wall_mm",
        ),
        (
            json!({"curve": {"preset": "arc"}, "design": {"balloon": {"material": {"model": "rubber"}}}}),
            "design.balloon.material",
        ),
        (
            json!({"curve": {"preset": "arc"}, "design": {"patches": []}}),
            "design.patches",
        ),
    ];
    for (body, field) in cases {
        let response = api.post("/v1/jobs", &body).await;
        let problem = assert_problem(response, 422, None).await;
        let named = problem["field"].as_str().unwrap_or("");
        assert!(
            named.starts_with(field),
            "{body}: expected field {field:?}, got {problem}"
        );
        println!("{named:<28} {}", problem["detail"]);
    }

    // Too many points.
    let points: Vec<[f64; 3]> = (0..100_001).map(|i| [i as f64, 0.0, 0.0]).collect();
    let response = api
        .post("/v1/jobs", &json!({"curve": {"points": points}}))
        .await;
    assert_problem(response, 422, Some("curve.points")).await;

    // An oversized body (the limit is 8 MiB).
    let big = format!(
        "{{\"curve\": {{\"csv\": \"{}\"}}}}",
        "0,0,0\\n".repeat(1_500_000)
    );
    // The server reads and discards a declared body it refuses before it
    // answers, so the answer reaches a client that is still writing.
    let response = post_raw(&api, "/v1/jobs", json_type, big.into_bytes()).await;
    assert_eq!(response.headers()["connection"], "close");
    assert_problem(response, 413, None).await;

    // A client that asks before uploading (`Expect: 100-continue`, as curl
    // does) is refused from the declared length alone: no `100 Continue`, and
    // the answer arrives without a byte of the body sent.
    let head = oversized_head_only(&server).await;
    assert!(head.starts_with("HTTP/1.1 413"), "{head}");
    assert!(!head.contains("100 Continue"), "{head}");
    assert!(head.contains("application/problem+json"), "{head}");
    assert!(head.contains("over the limit"), "{head}");

    // Nothing was queued by any of it.
    let list: Value = api.get("/v1/jobs").await.json().await.unwrap();
    assert!(list["jobs"].as_array().unwrap().is_empty());
}

#[tokio::test(flavor = "multi_thread")]
async fn bad_queries_headers_routes_and_quick_looks() {
    let server = Server::start();
    let api = server.api();
    assert_problem(api.get("/v1/jobs?status=lost").await, 400, Some("status")).await;
    assert_problem(api.get("/v1/jobs?limit=0").await, 400, Some("limit")).await;
    assert_problem(api.get("/v1/jobs/no-such-job").await, 404, None).await;
    // Bytes PostgreSQL refuses in text never reach the store (schemathesis
    // found a 500 there): a cursor that is not a job id is the user's
    // mistake, an id that is not one is no job.
    let nul_cursor = "/v1/jobs?status=failed&cursor=%00+w%08%14&limit=440";
    assert_problem(api.get(nul_cursor).await, 400, Some("cursor")).await;
    assert_problem(api.get("/v1/jobs/%00x").await, 404, None).await;
    assert_problem(api.get("/v1/jobs/%00x/events").await, 404, None).await;
    assert_problem(api.get("/v1/nowhere").await, 404, None).await;
    let wrong_method = api
        .request(reqwest::Method::PUT, "/v1/jobs")
        .send()
        .await
        .unwrap();
    assert_problem(wrong_method, 405, None).await;
    let id = api.submit(&quick_job(10)).await;
    let response = api
        .request(reqwest::Method::GET, &format!("/v1/jobs/{id}/events"))
        .header("Last-Event-ID", "yesterday")
        .send()
        .await
        .unwrap();
    assert_problem(response, 400, Some("Last-Event-ID")).await;
    let bad_key = api
        .request(reqwest::Method::POST, "/v1/jobs")
        .header("Idempotency-Key", "")
        .json(&quick_job(10))
        .send()
        .await
        .unwrap();
    assert_problem(bad_key, 400, Some("Idempotency-Key")).await;

    // A patch off the balloon, a NaN-free but impossible mesh, an unknown field.
    let off = json!({"design": {"balloon": {"length_mm": 60},
        "patches": [{"x_mm": 0, "y_mm": 500, "h_mm": 20, "w_mm": 2, "theta_deg": 0}]}});
    assert_problem(
        api.post("/v1/simulate", &off).await,
        422,
        Some("design.patches[0].y_mm"),
    )
    .await;
    let coarse = json!({"design": {"patches": []}, "mesh_mm": 0.01});
    assert_problem(
        api.post("/v1/simulate", &coarse).await,
        422,
        Some("mesh_mm"),
    )
    .await;
    let straight = json!({"design": {"patches": []}, "mesh_mm": 2, "straight_mm": 1});
    assert_problem(
        api.post("/v1/simulate", &straight).await,
        422,
        Some("straight_mm"),
    )
    .await;
    let angle = json!({"design": {"patches": [{"x_mm": 0, "y_mm": 30, "h_mm": 20, "w_mm": 2, "theta_deg": 95}]}});
    assert_problem(
        api.post("/v1/simulate", &angle).await,
        422,
        Some("design.patches[0].theta_deg"),
    )
    .await;
    // A patch a kilometre long: past what the description allows.
    let huge = json!({"design": {"patches": [{"x_mm": 0, "y_mm": 30, "h_mm": 2e6, "w_mm": 2, "theta_deg": 0}]}});
    assert_problem(
        api.post("/v1/simulate", &huge).await,
        422,
        Some("design.patches[0].h_mm"),
    )
    .await;
    let typo = json!({"design": {"patches": [], "presure_kpa": 20}});
    assert_problem(
        api.post("/v1/simulate", &typo).await,
        422,
        Some("design.presure_kpa"),
    )
    .await;
    let rule = json!({"design": {"patches": []}, "cut_elements": "voigt"});
    assert_problem(
        api.post("/v1/simulate", &rule).await,
        422,
        Some("cut_elements"),
    )
    .await;
    let ksa = json!({"curve": {"preset": "arc"}, "kappa_tol": -1});
    assert_problem(api.post("/v1/ksa", &ksa).await, 422, Some("kappa_tol")).await;

    // The server is fine afterwards.
    let done = api
        .wait_for(
            &id,
            &["succeeded", "failed"],
            std::time::Duration::from_secs(60),
        )
        .await;
    assert_eq!(done["status"], "succeeded");
}
