//! The page's calibration, from a built balloon's scan compared with its
//! design: calibrate and save a balloon profile, watch the calibration job
//! to its answer, and design with the profile (`browser.rs` drives a design
//! to the comparison first).

use std::time::Duration;

use serde_json::json;

use crate::webdriver::Session;

/// On a job page whose comparison has just been made (of a scan of the
/// predicted surface: the built balloon is the design's own).
pub async fn calibrate_to_the_compared_balloon(page: &Session) {
    page.wait_true(
        "return !document.querySelector('#calibrate-offer').hidden",
        "the offer to calibrate",
    )
    .await;
    page.type_into("#profile-name", "scanned-1").await;
    page.click("#calibrate").await;
    page.wait_text("#job-heading", "the calibration's page", |t| {
        t.starts_with("Calibration")
    })
    .await;
    let patience = Duration::from_secs(180);
    let facts = page
        .wait_text_for("#job-facts", "the calibration's answer", patience, |t| {
            t.contains("misfit") && t.contains("built balloon 1")
        })
        .await;
    assert!(facts.contains("patch_modulus"), "{facts}");
    page.resize(1280, 800).await;
    page.screenshot(&crate::browser::screenshots().join("calibration.png"))
        .await;
    // The balloon built as designed: the materials it was designed with.
    let fitted = page
        .execute("return window.patchwork.calibration.parameters", json!([]))
        .await;
    for p in fitted.as_array().unwrap() {
        let (value, start) = (p["value"].as_f64().unwrap(), p["start"].as_f64().unwrap());
        assert!((value / start - 1.0).abs() < 0.03, "{fitted}");
    }
    assert_eq!(
        page.execute(
            "return document.querySelector('#calibration-downloads').hidden",
            json!([])
        )
        .await,
        json!(false)
    );
    // On to a design with the profile saved.
    page.click("#design-with-profile").await;
    page.wait_true(
        "return document.querySelector('#balloon-profile').value === 'scanned-1'",
        "the design form chooses the saved profile",
    )
    .await;
}
