//! The web app in a real browser: headless Chromium driven over WebDriver
//! against `patchwork serve` on port 0. Screenshots of the three main views
//! go to `target/browser/`; with `PATCHWORK_DOCS_SCREENSHOT=1` the result
//! view (of the grasp preset, designed at draft fidelity) also goes to
//! `docs/images/web-app.png`, the README's picture.

use std::path::{Path, PathBuf};
use std::time::Duration;

use serde_json::json;

use crate::support::*;
use crate::webdriver::{Driver, Session, downloaded};

pub fn screenshots() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("target/browser")
}

/// The page at 1280×800 with downloads going to `downloads`.
pub async fn open(driver: &Driver, server: &Server, downloads: &Path) -> Session {
    let session = driver.session(1280, 800, downloads).await;
    session.goto(&format!("{}/", server.base)).await;
    session
}

/// A CSV of points the way a lab would export it.
fn write_csv(dir: &Path, preset: &[&str]) -> PathBuf {
    let output = std::process::Command::new(env!("CARGO_BIN_EXE_patchwork"))
        .arg("preset")
        .args(preset)
        .output()
        .unwrap();
    assert!(output.status.success());
    let path = dir.join("target-curve.csv");
    std::fs::write(&path, output.stdout).unwrap();
    path
}

/// From a CSV file to a downloaded DXF, in the browser alone: the file is
/// read and drawn in 3D, the design runs with live progress, the result
/// shows (centreline, surface, metrics), and patches.dxf downloads and
/// passes ezdxf's audit.
#[tokio::test(flavor = "multi_thread")]
async fn a_csv_file_becomes_a_downloaded_dxf() {
    let docs = std::env::var_os("PATCHWORK_DOCS_SCREENSHOT").is_some();
    let server = Server::start();
    let api = server.api();
    let driver = Driver::start();
    let dir = tempfile::tempdir().unwrap();
    let (curve, budget): (&[&str], &str) = if docs {
        (&["grasp"], "")
    } else {
        (&["helix", "radius_mm=15", "pitch_mm=40", "turns=0.6"], "30")
    };
    let csv = write_csv(dir.path(), curve);
    let page = open(&driver, &server, dir.path()).await;

    page.click("[data-source=file]").await;
    page.choose_file("#curve-file", &csv).await;
    let info = page
        .wait_text("#curve-info", "the curve's length", |t| {
            t.contains("mm long")
        })
        .await;
    assert!(info.contains("KSA's first guess"), "{info}");
    page.wait_true(
        "return window.patchwork.view.inkFraction() > 0.01",
        "the 3D view draws the curve",
    )
    .await;
    let profiles = page
        .execute(
            "return document.querySelectorAll('#profiles path').length",
            json!([]),
        )
        .await;
    assert!(profiles.as_u64().unwrap() >= 2, "κ and τ are plotted");
    page.screenshot(&screenshots().join("curve.png")).await;

    page.select("#fidelity", "draft").await;
    page.type_into("#budget", budget).await;
    // Kept clear of itself and robust: the form's boxes reach the run.
    page.click("#keep-clear").await;
    page.click("#robust").await;
    page.click("#submit").await;
    page.wait_text("#job-heading", "the job's view", |t| t.starts_with("Job "))
        .await;
    page.wait_true(
        "return document.querySelectorAll('#progress-chart path').length > 0",
        "progress events drawn",
    )
    .await;
    let facts = page.text("#job-facts").await;
    assert!(facts.contains("evaluations"), "{facts}");
    // The job's plan and its stages' budgets, as the server answers them.
    assert!(facts.contains("seed → reach → search"), "{facts}");
    assert!(facts.contains("search: "), "{facts}");
    page.screenshot(&screenshots().join("progress.png")).await;

    page.wait_text_for("#job-status", "success", Duration::from_secs(600), |t| {
        t == "succeeded"
    })
    .await;
    page.wait_true(
        "return window.patchwork.view.has('surface') && window.patchwork.view.has('design')",
        "the result's centreline and surface drawn",
    )
    .await;
    // The page aligns the centreline to the target itself (align.js): its
    // shape error is the server's, computed the same way.
    let fit = page
        .execute("return window.patchwork.resultFit", json!([]))
        .await;
    let (ours, server) = (
        fit["percent"].as_f64().unwrap(),
        fit["server"].as_f64().unwrap(),
    );
    assert!(
        (ours / server - 1.0).abs() < 0.01,
        "page {ours} % vs server {server} %"
    );
    let kept_clear = page
        .execute("return window.patchwork.result.input.keep_clear", json!([]))
        .await;
    assert_eq!(kept_clear, json!(true), "the box ticked reaches the run");
    // The layouts the run tried are listed whenever there was more than one.
    let tried = page
        .execute(
            "return (window.patchwork.result.layouts ?? []).length",
            json!([]),
        )
        .await;
    let facts = page.text("#job-facts").await;
    assert_eq!(
        facts.contains("layouts tried"),
        tried.as_u64().unwrap() >= 2,
        "{facts}"
    );
    // Every design reports its spread at the tolerances and what matters
    // most; the patches among the three largest sources are marked.
    let spread = page.text("[data-fact='spread at the tolerances']").await;
    assert!(
        spread.contains("mm RMS") && spread.contains("expected shape error as built"),
        "{spread}"
    );
    // ... and draws it as a band around the predicted centreline.
    let band = page
        .execute(
            "return [window.patchwork.view.has('design-band'), \
             window.patchwork.result.spread.band_mm.length]",
            json!([]),
        )
        .await;
    assert_eq!(band, json!([true, 64]), "the spread's band");
    let most = page.text("[data-fact='matters most']").await;
    assert!(most.contains("mm RMS, tip"), "{most}");
    // The robust refine's two designs, and which stands.
    let robust = page.text("[data-fact='robust design']").await;
    assert!(
        robust.contains("nominal design") && robust.contains("% expected"),
        "{robust}"
    );
    let marked = page
        .execute(
            "return [document.querySelectorAll('#patch-table tr.sensitive').length, \
             (window.patchwork.result.spread.contributors.slice(0, 3)\
               .filter((c) => c.source === 'patch').map((c) => c.patch)).length]",
            json!([]),
        )
        .await;
    let (rows, patch_sources) = (marked[0].as_u64().unwrap(), marked[1].as_u64().unwrap());
    assert!(
        rows >= 1.min(patch_sources) && rows <= patch_sources,
        "{marked}"
    );
    page.screenshot(&screenshots().join("result.png")).await;
    if docs {
        let image = Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/images/web-app.png");
        page.screenshot(&image).await;
    }

    // A design checked by hand: P1 turned by 10°, simulated, drawn.
    let theta = "input[data-patch=\"0\"][data-key=\"theta_deg\"]";
    let value = page
        .execute(
            &format!("return document.querySelector('{theta}').value"),
            json!([]),
        )
        .await;
    let turned = value.as_str().unwrap().parse::<f64>().unwrap() + 10.0;
    page.type_into(theta, &turned.to_string()).await;
    page.click("#simulate").await;
    let checked = page
        .wait_text("#simulate-info", "the edited design's shape error", |t| {
            t.starts_with("edited design: shape error")
        })
        .await;
    assert!(checked.contains('%'), "{checked}");
    assert_eq!(
        page.execute("return window.patchwork.view.has('edited')", json!([]))
            .await,
        json!(true)
    );

    // The balloon built: its centreline (here the prediction's own, given
    // tip to base) uploaded and compared; drawn over the design.
    let predicted = page
        .execute("return window.patchwork.result.centreline_mm", json!([]))
        .await;
    let mut lines: Vec<String> = predicted
        .as_array()
        .unwrap()
        .iter()
        .map(|p| format!("{},{},{}", p[0], p[1], p[2]))
        .collect();
    lines.reverse();
    let measured = dir.path().join("measured.csv");
    std::fs::write(&measured, lines.join("\n")).unwrap();
    let count_paths = "return document.querySelectorAll('#profiles path').length";
    let before = page.execute(count_paths, json!([])).await;
    page.choose_file("#measured-file", &measured).await;
    page.click("#compare").await;
    let compared = page
        .wait_text("#compare-facts", "the comparison's figures", |t| {
            t.contains("vs prediction")
        })
        .await;
    assert!(compared.contains("given tip to base"), "{compared}");
    let comparison = page
        .execute("return window.patchwork.comparison", json!([]))
        .await;
    assert!(
        comparison["against_prediction"]["shape_error_mm"]
            .as_f64()
            .unwrap()
            < 1e-6
    );
    let rows = page
        .execute(
            "return document.querySelectorAll('#compare-table tbody tr').length",
            json!([]),
        )
        .await;
    assert_eq!(rows, json!(comparison["patches"].as_array().unwrap().len()));
    // The built balloon's κ and τ join the profiles.
    let after = page.execute(count_paths, json!([])).await;
    assert!(after.as_u64() > before.as_u64(), "{before} → {after}");
    assert_eq!(
        page.execute("return window.patchwork.view.has('measured')", json!([]))
            .await,
        json!(true)
    );

    // A scan of it (the predicted surface as a PLY mesh) compares too.
    let design = page
        .execute("return window.patchwork.result.design", json!([]))
        .await;
    let scan = dir.path().join("scan.ply");
    std::fs::write(&scan, crate::measure::surface_ply(&api, &design).await).unwrap();
    page.choose_file("#measured-file", &scan).await;
    page.click("#compare").await;
    page.wait_text("#compare-facts", "the scan's figures", |t| {
        t.contains("cross-sections")
    })
    .await;
    let scanned = page
        .execute("return window.patchwork.comparison.scan.points", json!([]))
        .await;
    assert!(scanned.as_u64().unwrap() >= 300_000, "{scanned}");

    page.click("[data-file=\"patches.dxf\"]").await;
    let dxf = downloaded(dir.path(), "patches.dxf").await;
    assert_eq!(crate::common::ezdxf_errors(&dxf), 0);

    // On a tablet held upright the views stack: nothing runs off the side.
    page.resize(820, 1180).await;
    page.wait_true(
        "return document.documentElement.scrollWidth <= window.innerWidth \
         && getComputedStyle(document.querySelector('main')).gridTemplateColumns.split(' ').length == 1",
        "a single column without horizontal scrolling at 820 px",
    )
    .await;
    page.screenshot(&screenshots().join("result-tablet.png"))
        .await;
    // From the scan compared, a calibration and a profile to design with.
    crate::browser_calibrate::calibrate_to_the_compared_balloon(&page).await;
    page.quit().await;
}

/// The server killed (kill -9) while the page watches a job, and started
/// again on the same address: the page reconnects by itself, the job
/// resumes from its checkpoint, and the page has shown every event of the
/// job exactly once.
#[tokio::test(flavor = "multi_thread")]
async fn the_page_reconnects_after_the_server_dies_and_misses_no_event() {
    let dir = tempfile::tempdir().unwrap();
    let addr = std::net::TcpListener::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap();
    let options = Options {
        workers: Some(1),
        db: Some(dir.path().join("patchwork.db")),
        addr: Some(addr),
        ..Options::default()
    };
    let mut server = Server::with(options.clone());
    let id = server.api().submit(&long_job(300)).await;
    let driver = Driver::start();
    let session = driver.session(1280, 800, dir.path()).await;
    session.goto(&format!("{}/#/jobs/{id}", server.base)).await;
    session
        .wait_true(
            "return window.patchwork.job.progress.length >= 2",
            "progress shown before the kill",
        )
        .await;
    server.kill_hard();
    let server = Server::with(options);
    session
        .wait_text_for("#job-status", "success", Duration::from_secs(600), |t| {
            t == "succeeded"
        })
        .await;
    let page = session
        .execute(
            "return {seen: window.patchwork.job.seen, reconnects: window.patchwork.job.reconnects}",
            json!([]),
        )
        .await;
    assert!(page["reconnects"].as_u64().unwrap() >= 1, "{page}");
    let shown: Vec<u64> = page["seen"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_u64().unwrap())
        .collect();
    let stored: Vec<u64> = read_events(&server.api(), &id, None, |_| false)
        .await
        .iter()
        .map(|e| e.id)
        .collect();
    assert_eq!(shown, stored, "every event once, in order");
    session.quit().await;
}

/// A malformed CSV: the server's message (with its line) appears beside the
/// curve field, and nothing is submitted.
#[tokio::test(flavor = "multi_thread")]
async fn a_malformed_csv_shows_the_servers_message() {
    let server = Server::start();
    let driver = Driver::start();
    let dir = tempfile::tempdir().unwrap();
    let page = open(&driver, &server, dir.path()).await;
    page.click("[data-source=paste]").await;
    page.type_into("#curve-text", "x,y,z\n0,0,0\n1,0\n2,0,0\n3,0,0\n")
        .await;
    let message = page
        .wait_text("#curve-error", "the server's message", |t| !t.is_empty())
        .await;
    assert!(message.contains("line 3"), "{message}");
    assert!(message.contains("3 columns"), "{message}");
    page.click("#submit").await;
    let beside = page
        .wait_text("#curve-error", "the job's refusal", |t| {
            t.contains("line 3")
        })
        .await;
    assert!(beside.contains("3 columns"), "{beside}");
    let jobs = server
        .api()
        .get("/v1/jobs")
        .await
        .json::<serde_json::Value>()
        .await
        .unwrap();
    assert_eq!(
        jobs["jobs"].as_array().unwrap().len(),
        0,
        "nothing submitted"
    );
    page.quit().await;
}

/// The form's time limit reaches the run: a limit spent by the time the
/// seed is placed leaves the seed's design, verified, and the result says
/// what the limit cut short.
#[tokio::test(flavor = "multi_thread")]
async fn a_time_limit_from_the_form_cuts_the_run_short_and_says_so() {
    let server = Server::start();
    let driver = Driver::start();
    let dir = tempfile::tempdir().unwrap();
    let csv = write_csv(dir.path(), &["hook"]);
    let page = open(&driver, &server, dir.path()).await;
    page.click("[data-source=file]").await;
    page.choose_file("#curve-file", &csv).await;
    page.wait_text("#curve-info", "the curve's length", |t| {
        t.contains("mm long")
    })
    .await;
    page.select("#fidelity", "draft").await;
    page.type_into("#time-limit", "0.001").await;
    page.click("#submit").await;
    page.wait_text_for("#job-status", "success", Duration::from_secs(120), |t| {
        t == "succeeded"
    })
    .await;
    let facts = page
        .wait_text("#job-facts", "the result's facts", |t| {
            t.contains("shape error")
        })
        .await;
    assert!(facts.contains("reached in the seed"), "{facts}");
    assert!(facts.contains("skipped: reach, search"), "{facts}");
    let limited = page
        .execute("return window.patchwork.result.time_limited", json!([]))
        .await;
    assert_eq!(limited["limit_s"], json!(0.001), "{limited}");
    page.quit().await;
}

/// With API keys: the page asks for one, says when a key is refused, and
/// lists only the jobs of the key it was given.
#[tokio::test(flavor = "multi_thread")]
async fn with_keys_the_page_asks_and_lists_only_its_own_jobs() {
    let server = Server::with(Options {
        keys: Some("alice-key,bob-key"),
        ..Options::default()
    });
    let alice = server.as_key("alice-key").submit(&quick_job(5)).await;
    let bob = server.as_key("bob-key").submit(&quick_job(5)).await;
    let driver = Driver::start();
    let dir = tempfile::tempdir().unwrap();
    let page = open(&driver, &server, dir.path()).await;
    page.wait_text("#key-message", "a request for a key", |t| {
        t.contains("needs an API key")
    })
    .await;
    page.type_into("#api-key", "mallory-key").await;
    page.click("#key-form button").await;
    page.wait_text("#key-message", "the refusal", |t| t.contains("refused"))
        .await;
    page.type_into("#api-key", "bob-key").await;
    page.click("#key-form button").await;
    page.wait_text("#curve-info", "the preset read with bob's key", |t| {
        t.contains("mm long")
    })
    .await;
    page.click("#nav-jobs").await;
    page.find(&format!("tr[data-job=\"{bob}\"]")).await;
    let listed = page
        .execute(
            "return [...document.querySelectorAll('#jobs-table tr[data-job]')].map(r => r.dataset.job)",
            json!([]),
        )
        .await;
    assert_eq!(listed, json!([bob]), "alice's job {alice} is not listed");
    page.screenshot(&screenshots().join("jobs.png")).await;
    page.quit().await;
}
