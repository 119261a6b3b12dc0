//! API keys: no key or an unknown key is a 401; a key sees only its own jobs.

use serde_json::Value;

use crate::support::*;

#[tokio::test(flavor = "multi_thread")]
async fn each_key_sees_only_its_own_jobs() {
    let server = Server::with(Options {
        keys: Some("key-alice, key-bob"),
        ..Options::default()
    });
    let anonymous = server.api();
    assert_problem(anonymous.get("/v1/jobs").await, 401, Some("Authorization")).await;
    let response = anonymous.post("/v1/jobs", &quick_job(10)).await;
    assert_eq!(response.headers()["www-authenticate"], "Bearer");
    assert_problem(response, 401, None).await;
    assert_problem(
        server.as_key("key-mallory").get("/v1/presets").await,
        401,
        None,
    )
    .await;
    // Operations routes stay open.
    assert_eq!(anonymous.get("/healthz").await.status(), 200);

    let alice = server.as_key("key-alice");
    let bob = server.as_key("key-bob");
    let id = alice.submit(&quick_job(10)).await;
    assert_eq!(alice.get(&format!("/v1/jobs/{id}")).await.status(), 200);
    for path in [
        format!("/v1/jobs/{id}"),
        format!("/v1/jobs/{id}/events"),
        format!("/v1/jobs/{id}/iterations"),
        format!("/v1/jobs/{id}/result"),
        format!("/v1/jobs/{id}/files/patches.dxf"),
    ] {
        assert_problem(bob.get(&path).await, 404, None).await;
    }
    let cancel = bob
        .post(&format!("/v1/jobs/{id}/cancel"), &Value::Null)
        .await;
    assert_problem(cancel, 404, None).await;
    let delete = bob
        .request(reqwest::Method::DELETE, &format!("/v1/jobs/{id}"))
        .send()
        .await
        .unwrap();
    assert_problem(delete, 404, None).await;
    let bobs: Value = bob.get("/v1/jobs").await.json().await.unwrap();
    assert!(bobs["jobs"].as_array().unwrap().is_empty());
    let alices: Value = alice.get("/v1/jobs").await.json().await.unwrap();
    assert_eq!(alices["jobs"][0]["id"], id.as_str());
    // Bob's idempotency keys are his own.
    let job = alice
        .wait_for(
            &id,
            &["succeeded", "failed"],
            std::time::Duration::from_secs(60),
        )
        .await;
    assert_eq!(job["status"], "succeeded");
}

#[tokio::test(flavor = "multi_thread")]
async fn keys_and_cors_origins_from_the_config_file() {
    let server = Server::with(Options {
        config: Some("api_keys = [\"from-file\"]\ncors_origins = [\"https://lab.example\"]\n"),
        ..Options::default()
    });
    assert_problem(server.api().get("/v1/presets").await, 401, None).await;
    let keyed = server.as_key("from-file");
    assert_eq!(keyed.get("/v1/presets").await.status(), 200);
    // A browser's preflight from the lab's origin is allowed; another origin is not.
    let preflight = |origin: &'static str| {
        keyed
            .request(reqwest::Method::OPTIONS, "/v1/jobs")
            .header("Origin", origin)
            .header("Access-Control-Request-Method", "POST")
            .header(
                "Access-Control-Request-Headers",
                "authorization, content-type",
            )
            .send()
    };
    let allowed = preflight("https://lab.example").await.unwrap();
    assert_eq!(
        allowed.headers()["access-control-allow-origin"],
        "https://lab.example"
    );
    let other = preflight("https://elsewhere.example").await.unwrap();
    assert!(!other.headers().contains_key("access-control-allow-origin"));
}
