//! A job as the API shows it (`JobView`), whatever its kind: its kind, read
//! from its stored spec, decides its files.

use serde::Serialize;
use serde_json::{Value, json};

use super::job_state::JobStatus;
use super::spec::{JobKind, JobSpec};
use super::store::JobRow;

/// The files of a finished design job.
pub const FILES: [&str; 6] = [
    "patches.dxf",
    "template.dxf",
    "template.svg",
    "profiles.svg",
    "design.json",
    "design.csv",
];

/// The files of a finished calibration job.
pub const CALIBRATION_FILES: [&str; 2] = ["calibration.json", "options.json"];

/// The files a job of `kind` ends with.
pub fn files_of(kind: JobKind) -> &'static [&'static str] {
    match kind {
        JobKind::Design => &FILES,
        JobKind::Calibrate => &CALIBRATION_FILES,
    }
}

/// A stored job's kind (a job stored before specs is a design).
pub fn kind_of(row: &JobRow) -> JobKind {
    (row.spec.as_deref())
        .and_then(JobSpec::stored_kind)
        .unwrap_or(JobKind::Design)
}

/// The job resource.
#[derive(Debug, Serialize)]
pub struct JobView {
    pub id: String,
    pub kind: JobKind,
    pub status: JobStatus,
    pub created_at: String,
    pub updated_at: String,
    pub progress: Value,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
    pub links: Value,
}

impl JobView {
    pub fn new(row: &JobRow) -> JobView {
        let base = format!("/v1/jobs/{}", row.id);
        let kind = kind_of(row);
        let files: serde_json::Map<String, Value> = files_of(kind)
            .iter()
            .map(|name| (name.to_string(), json!(format!("{base}/files/{name}"))))
            .collect();
        JobView {
            id: row.id.clone(),
            kind,
            status: row.status,
            created_at: row.created_at.clone(),
            updated_at: row.updated_at.clone(),
            progress: row
                .progress
                .as_deref()
                .and_then(|p| serde_json::from_str(p).ok())
                .unwrap_or(Value::Null),
            error: row.error.clone(),
            links: json!({
                "self": base,
                "events": format!("{base}/events"),
                "iterations": format!("{base}/iterations"),
                "result": format!("{base}/result"),
                "cancel": format!("{base}/cancel"),
                "files": files,
            }),
        }
    }
}
