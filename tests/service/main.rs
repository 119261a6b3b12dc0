//! Black-box tests of `patchwork serve` over real HTTP: each test starts the
//! binary on port 0 with a fresh SQLite file. The web app's tests drive a
//! real headless Chromium (`browser.rs`, over `webdriver.rs`).

#[path = "../common/mod.rs"]
mod common;
mod schema;
mod support;
mod webdriver;

// libtest starts tests in the order of their names, two at a time here:
// schemathesis' run, the longest, is named to start first, not last.
mod access;
mod api_description;
mod bad_input;
mod browser;
mod browser_calibrate;
mod calibrate;
mod copy_jobs;
mod lifecycle;
mod measure;
mod nodes;
mod outage;
mod page_routes;
mod recovery;
