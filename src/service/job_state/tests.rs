use super::{Ending, EventKind, JobStatus};

/// The names inside the first `(...)` or `[...]` after `marker` in `text`,
/// unquoted.
fn listed_after(text: &str, marker: &str, close: char) -> Vec<String> {
    let start = text
        .find(marker)
        .unwrap_or_else(|| panic!("{marker:?} not found"))
        + marker.len();
    let end = start + text[start..].find(close).expect("list not closed");
    text[start..end]
        .split(',')
        .map(|s| s.trim().trim_matches(['\'', '"']).to_string())
        .filter(|s| !s.is_empty())
        .collect()
}

/// The kinds after which a job sends nothing more, by name.
fn final_events() -> Vec<&'static str> {
    EventKind::ALL
        .into_iter()
        .filter(|k| k.is_final())
        .map(EventKind::as_str)
        .collect()
}

fn status_names() -> Vec<String> {
    JobStatus::ALL.map(|s| s.as_str().to_string()).to_vec()
}

#[test]
fn names_read_back_and_serialise_as_written() {
    for status in JobStatus::ALL {
        assert_eq!(status.as_str().parse::<JobStatus>(), Ok(status));
        assert_eq!(serde_json::to_value(status).unwrap(), status.as_str());
    }
    for kind in EventKind::ALL {
        assert_eq!(kind.as_str().parse::<EventKind>(), Ok(kind));
        assert_eq!(serde_json::to_value(kind).unwrap(), kind.as_str());
    }
    assert!("Queued".parse::<JobStatus>().is_err());
    assert!("canceled".parse::<JobStatus>().is_err());
    assert_eq!(
        JobStatus::names(),
        "queued, running, succeeded, failed, cancelled"
    );
}

#[test]
fn a_job_ends_succeeded_failed_or_cancelled_and_its_final_event_says_which() {
    let ended: Vec<&str> = JobStatus::ALL
        .into_iter()
        .filter(|s| s.is_terminal())
        .map(JobStatus::as_str)
        .collect();
    assert_eq!(ended, ["succeeded", "failed", "cancelled"]);
    assert_eq!(final_events(), ["done", "failed", "cancelled"]);
    for ending in [Ending::Failed, Ending::Cancelled] {
        assert!(ending.status().is_terminal() && ending.event().is_final());
        assert_eq!(ending.status().as_str(), ending.event().as_str());
    }
}

#[test]
fn the_schemas_check_constraint_allows_exactly_the_statuses() {
    for schema in [
        include_str!("../../../migrations/sqlite/0001_jobs.sql"),
        include_str!("../../../migrations/postgres/0001_jobs.sql"),
    ] {
        assert_eq!(
            listed_after(schema, "CHECK (status IN (", ')'),
            status_names()
        );
    }
}

#[test]
fn every_status_the_statements_write_or_test_is_a_status() {
    let sources = [
        include_str!("../store/statements.rs"),
        include_str!("../store/sqlite.rs"),
        include_str!("../store/postgres.rs"),
        include_str!("../store/transfer.rs"),
        include_str!("../../../migrations/postgres/0003_announcements.sql"),
    ];
    let mut seen = 0;
    for source in sources {
        for (at, _) in source.match_indices("status = '") {
            let rest = &source[at + "status = '".len()..];
            let name = &rest[..rest.find('\'').unwrap()];
            assert!(name.parse::<JobStatus>().is_ok(), "status '{name}' in SQL");
            seen += 1;
        }
        for (at, _) in source.match_indices("status NOT IN (") {
            for name in listed_after(&source[at..], "IN (", ')') {
                assert!(name.parse::<JobStatus>().is_ok(), "status '{name}' in SQL");
                seen += 1;
            }
        }
    }
    assert!(seen >= 10, "only {seen} statuses found in the SQL");
}

#[test]
fn the_api_document_lists_exactly_the_statuses() {
    let openapi = include_str!("../../../openapi.yaml");
    let schema = &openapi[openapi.find("    JobStatus:").expect("JobStatus schema")..];
    assert_eq!(listed_after(schema, "enum: [", ']'), status_names());
}

#[test]
fn the_web_app_ends_a_stream_on_the_final_events_and_handles_every_kind() {
    let events_js = include_str!("../../../web/static/js/events.js");
    assert_eq!(
        listed_after(events_js, "const FINAL = new Set([", ']'),
        final_events()
    );
    let watch_js = include_str!("../../../web/static/js/watch.js");
    for kind in EventKind::ALL {
        let handled = format!("event === \"{}\"", kind.as_str());
        assert!(watch_js.contains(&handled), "watch.js lacks {handled}");
    }
}

/// Every stage a plan may announce is in the API document's `Stage` enum,
/// in order, followed by a calibration's one stage, and each has its label
/// in the web app.
#[test]
fn the_api_document_and_the_web_app_know_every_stage() {
    use patchwork_core::inverse::StageName;
    let mut names: Vec<String> = StageName::ALL
        .iter()
        .map(|s| {
            serde_json::to_value(s)
                .unwrap()
                .as_str()
                .unwrap()
                .to_string()
        })
        .collect();
    assert_eq!(names.last().map(String::as_str), Some("robust"));
    names.push("calibrate".into());
    let openapi = include_str!("../../../openapi.yaml");
    let schema = &openapi[openapi.find("    Stage:").expect("Stage schema")..];
    assert_eq!(listed_after(schema, "enum: [", ']'), names);
    let watch_js = include_str!("../../../web/static/js/watch.js");
    let labels = &watch_js[watch_js.find("const STAGES = {").expect("STAGES")..];
    let labels = &labels[..labels.find("};").unwrap()];
    for name in names.iter().map(String::as_str).chain(["queued"]) {
        assert!(
            labels.contains(&format!("\n  {name}: \"")),
            "no label for {name}"
        );
    }
}
