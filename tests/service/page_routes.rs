//! What the web app reads beyond the job routes: the curve as a job reads
//! it (POST /v1/curve), the inflated membrane (POST /v1/simulate with
//! `surface`), a job's own request and budget, and the embedded page with
//! its cache validators.

use serde_json::{Value, json};

use crate::support::*;

#[tokio::test(flavor = "multi_thread")]
async fn the_curve_is_answered_as_a_job_reads_it() {
    let server = Server::start();
    let api = server.api();
    let helix = json!({"preset": "helix", "params": {"radius_mm": 20, "pitch_mm": 60, "turns": 1}});
    let clean: Value = api
        .post("/v1/curve", &json!({"curve": helix}))
        .await
        .json()
        .await
        .unwrap();
    assert_schema("CurvePreview", &clean);
    // κ of a helix: r / (r² + c²), c = pitch / 2π.
    let c = 60.0 / std::f64::consts::TAU;
    let kappa = 20.0 / (400.0 + c * c);
    let middle = clean["curvature_per_mm"][200].as_f64().unwrap();
    assert!((middle / kappa - 1.0).abs() < 1e-3, "{middle} vs {kappa}");
    assert_eq!(clean["input"]["smoothing_mm"], 0.0);
    assert!(
        clean.get("given_mm").is_none(),
        "a clean curve is not moved"
    );

    // Noise on the points: found, smoothed, and the given points returned too.
    let noisy: Vec<[f64; 3]> = (0..300)
        .map(|i| {
            let t = i as f64 / 299.0 * std::f64::consts::PI;
            let wobble = if i % 2 == 0 { 0.4 } else { -0.4 };
            [50.0 * t.cos() + wobble, 50.0 * t.sin() - wobble, wobble]
        })
        .collect();
    let smoothed: Value = api
        .post("/v1/curve", &json!({"curve": {"points": noisy}}))
        .await
        .json()
        .await
        .unwrap();
    assert_schema("CurvePreview", &smoothed);
    assert!(smoothed["input"]["smoothing_mm"].as_f64().unwrap() > 0.0);
    assert_eq!(smoothed["given_mm"].as_array().unwrap().len(), 300);

    for (body, field) in [
        (json!({"curve": helix, "smooth_mm": -1}), "smooth_mm"),
        (
            json!({"curve": {"points": noisy}, "smooth_mm": 1000}),
            "smooth_mm",
        ),
        (json!({"curve": {"csv": "0,0,0\n1,1\n"}}), "curve.csv"),
    ] {
        let response = api.post("/v1/curve", &body).await;
        assert_eq!(response.status(), 422, "{body}");
        let problem: Value = response.json().await.unwrap();
        assert_eq!(problem["field"], field, "{problem}");
    }
}

#[tokio::test(flavor = "multi_thread")]
async fn simulate_answers_the_inflated_surface_when_asked() {
    let server = Server::start();
    let api = server.api();
    let design = json!({"balloon": {"length_mm": 60},
        "patches": [{"x_mm": 0, "y_mm": 30, "h_mm": 20, "w_mm": 2, "theta_deg": 0}]});
    let sim: Value = api
        .post(
            "/v1/simulate",
            &json!({"design": design, "mesh_mm": 2, "surface": true}),
        )
        .await
        .json()
        .await
        .unwrap();
    assert_schema("SimulateReport", &sim);
    let surface = &sim["surface"];
    let around = surface["around"].as_u64().unwrap() as usize;
    let nodes = surface["positions_mm"].as_array().unwrap();
    assert_eq!(
        (nodes.len() - 1) % around,
        0,
        "rings of {around} and a pole"
    );
    let share: Vec<f64> = surface["patch_share"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    assert_eq!(share.len(), nodes.len());
    // A 20 × 2 mm patch on a 60 mm balloon of radius 3.18 mm covers about
    // 2/20 of the circumference over a third of the length.
    let covered = share.iter().filter(|s| **s > 0.5).count() as f64 / share.len() as f64;
    assert!(covered > 0.01 && covered < 0.1, "{covered}");
    let plain: Value = api
        .post("/v1/simulate", &json!({"design": design, "mesh_mm": 2}))
        .await
        .json()
        .await
        .unwrap();
    assert!(plain.get("surface").is_none(), "only when asked");
}

#[tokio::test(flavor = "multi_thread")]
async fn a_job_answers_its_request_and_budget() {
    let server = Server::start();
    let api = server.api();
    // A job that runs for seconds: it is still running when cancelled below.
    let mut asked = long_job(400);
    asked["tuning"]["gentle_bends"] = json!(false);
    let id = api.submit(&asked).await;
    let job = api.job(&id).await;
    assert_schema("Job", &job);
    assert_eq!(job["search_budget"], 400);
    // Its plan, gentle bends off: no layout stage, and the budgets asked.
    let plan = job["plan"].as_str().unwrap();
    assert!(plan.starts_with("seed → reach → search"), "{plan}");
    assert!(!plan.contains("layout"), "{plan}");
    let budgets = job["stage_budgets"].as_str().unwrap();
    assert!(budgets.contains("search: 400 evaluations"), "{budgets}");
    assert_eq!(job["request"]["curve"], asked["curve"]);
    // The request answered is one the server takes again (no nulls).
    assert_eq!(job["request"]["tuning"], asked["tuning"]);
    assert_eq!(api.post("/v1/jobs", &job["request"]).await.status(), 202);
    // Cancel answers the same resource.
    let cancelled: Value = api
        .post(&format!("/v1/jobs/{id}/cancel"), &json!({}))
        .await
        .json()
        .await
        .unwrap();
    assert_schema("Job", &cancelled);
    assert_eq!(cancelled["request"]["tuning"], asked["tuning"]);
    let plain = json!({"curve": {"preset": "arc"}, "options": {"fidelity": "draft"}});
    let id = api.submit(&plain).await;
    let job = api.job(&id).await;
    assert!(
        job["search_budget"].as_u64().unwrap() > 7,
        "the fidelity's budget"
    );
    assert_eq!(
        job["plan"], "seed → reach → search → verify → length → refine → layout → spread",
        "draft's"
    );
    let listed: Value = api.get("/v1/jobs").await.json().await.unwrap();
    assert!(
        listed["jobs"][0].get("request").is_none(),
        "the list stays small"
    );
}

#[tokio::test(flavor = "multi_thread")]
async fn the_page_and_its_assets_are_served_with_validators() {
    let server = Server::start();
    let api = server.api();
    let page = api.get("/").await;
    assert_eq!(page.status(), 200);
    assert!(
        page.headers()["content-type"]
            .to_str()
            .unwrap()
            .starts_with("text/html")
    );
    assert_eq!(page.headers()["cache-control"], "no-cache");
    let etag = page.headers()["etag"].clone();
    let html = page.text().await.unwrap();
    // Every script and style the page names is served.
    for asset in ["/assets/app.css", "/assets/js/main.js"] {
        assert!(html.contains(asset), "{asset}");
        assert_eq!(api.get(asset).await.status(), 200, "{asset}");
    }
    let again = api
        .request(reqwest::Method::GET, "/")
        .header("If-None-Match", etag)
        .send()
        .await
        .unwrap();
    assert_eq!(again.status(), 304);
    let library = api
        .get("/assets/vendor/three-0.187.0/three.module.js")
        .await;
    assert_eq!(library.status(), 200);
    assert!(
        library.headers()["content-type"]
            .to_str()
            .unwrap()
            .starts_with("text/javascript")
    );
    assert!(
        library.headers()["cache-control"]
            .to_str()
            .unwrap()
            .contains("immutable")
    );
    let missing = api.get("/assets/js/nothing.js").await;
    assert_eq!(missing.status(), 404);
    assert!(
        missing.headers()["content-type"]
            .to_str()
            .unwrap()
            .contains("problem+json")
    );
}
