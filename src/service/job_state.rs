//! A job's status and the kinds of event it sends: the one place their names
//! are written. The store keeps them as text (`as_str`), the API and the
//! events stream send them by the same names, and the tests below hold the
//! SQL schema, `openapi.yaml` and the web app's scripts to them.

use std::fmt;
use std::str::FromStr;

use serde::{Deserialize, Serialize};

/// Where a job is. A job is queued, then running (a worker holds its lease),
/// and ends succeeded, failed or cancelled. A running job goes back to the
/// queue when its node shuts down, and a queued or running one may be
/// cancelled or fail.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum JobStatus {
    Queued,
    Running,
    Succeeded,
    Failed,
    Cancelled,
}

impl JobStatus {
    pub const ALL: [JobStatus; 5] = [
        JobStatus::Queued,
        JobStatus::Running,
        JobStatus::Succeeded,
        JobStatus::Failed,
        JobStatus::Cancelled,
    ];

    pub fn as_str(self) -> &'static str {
        match self {
            JobStatus::Queued => "queued",
            JobStatus::Running => "running",
            JobStatus::Succeeded => "succeeded",
            JobStatus::Failed => "failed",
            JobStatus::Cancelled => "cancelled",
        }
    }

    /// Whether the job has ended: nothing about it changes any more.
    pub fn is_terminal(self) -> bool {
        matches!(
            self,
            JobStatus::Succeeded | JobStatus::Failed | JobStatus::Cancelled
        )
    }

    /// Whether the job's result may still come: queued or running.
    pub fn is_pending(self) -> bool {
        !self.is_terminal()
    }

    /// Every status's name, for error messages ("queued, running, …").
    pub fn names() -> String {
        Self::ALL.map(JobStatus::as_str).join(", ")
    }
}

/// How a job ends other than by its worker's success: the status it takes
/// and the final event stored with it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Ending {
    Failed,
    Cancelled,
}

impl Ending {
    pub fn status(self) -> JobStatus {
        match self {
            Ending::Failed => JobStatus::Failed,
            Ending::Cancelled => JobStatus::Cancelled,
        }
    }

    pub fn event(self) -> EventKind {
        match self {
            Ending::Failed => EventKind::Failed,
            Ending::Cancelled => EventKind::Cancelled,
        }
    }
}

/// The kind of a job's server-sent event (its `event:` field).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum EventKind {
    /// The job entered a stage (`queued` first, then the plan's stages).
    Stage,
    /// What the balloon can reach, before the search.
    Reach,
    /// One generation of the search.
    Progress,
    /// The job succeeded: where its result is and its shape error.
    Done,
    /// The job failed: why.
    Failed,
    /// The job was cancelled.
    Cancelled,
}

impl EventKind {
    pub const ALL: [EventKind; 6] = [
        EventKind::Stage,
        EventKind::Reach,
        EventKind::Progress,
        EventKind::Done,
        EventKind::Failed,
        EventKind::Cancelled,
    ];

    pub fn as_str(self) -> &'static str {
        match self {
            EventKind::Stage => "stage",
            EventKind::Reach => "reach",
            EventKind::Progress => "progress",
            EventKind::Done => "done",
            EventKind::Failed => "failed",
            EventKind::Cancelled => "cancelled",
        }
    }

    /// Whether the job sends nothing after this event (it has ended).
    pub fn is_final(self) -> bool {
        matches!(
            self,
            EventKind::Done | EventKind::Failed | EventKind::Cancelled
        )
    }
}

/// A name that is not one of a [`JobStatus`]'s or an [`EventKind`]'s.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct UnknownName(pub String);

impl fmt::Display for UnknownName {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "unknown name {:?}", self.0)
    }
}

impl std::error::Error for UnknownName {}

/// `FromStr`, `TryFrom<String>` (how the store's rows decode the column)
/// and `Display` by the names of `as_str`.
macro_rules! named {
    ($type:ident) => {
        impl FromStr for $type {
            type Err = UnknownName;

            fn from_str(text: &str) -> Result<Self, UnknownName> {
                Self::ALL
                    .into_iter()
                    .find(|v| v.as_str() == text)
                    .ok_or_else(|| UnknownName(text.to_string()))
            }
        }

        impl TryFrom<String> for $type {
            type Error = UnknownName;

            fn try_from(text: String) -> Result<Self, UnknownName> {
                text.parse()
            }
        }

        impl fmt::Display for $type {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str(self.as_str())
            }
        }
    };
}

named!(JobStatus);
named!(EventKind);

#[cfg(test)]
mod tests;
