//! A whole job as it leaves one store and enters another (`patchwork
//! copy-jobs`): its row, every event, iteration and result file.

use sqlx::FromRow;

use super::Iteration;
use crate::service::job_state::{EventKind, JobStatus};

/// A job with everything it produced, as stored.
#[derive(Debug, Clone)]
pub struct JobExport {
    pub row: ExportRow,
    pub events: Vec<ExportEvent>,
    pub iterations: Vec<Iteration>,
    pub files: Vec<ExportFile>,
}

/// The job's own columns that outlive a lease.
#[derive(Debug, Clone, FromRow)]
pub struct ExportRow {
    pub id: String,
    pub owner: String,
    #[sqlx(try_from = "String")]
    pub status: JobStatus,
    pub request: String,
    pub spec: Option<String>,
    pub idempotency_key: Option<String>,
    pub created_at: String,
    pub updated_at: String,
    pub progress: Option<String>,
    pub error: Option<String>,
    pub checkpoint: Option<String>,
    pub result: Option<String>,
    pub attempt: i64,
    pub checkpoint_evaluations: i64,
}

#[derive(Debug, Clone, FromRow)]
pub struct ExportEvent {
    pub seq: i64,
    #[sqlx(try_from = "String")]
    pub kind: EventKind,
    pub data: String,
    pub created_at: String,
}

#[derive(Debug, Clone, FromRow)]
pub struct ExportFile {
    pub name: String,
    pub content_type: String,
    pub body: Vec<u8>,
}
