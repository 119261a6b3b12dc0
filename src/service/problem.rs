//! Errors as RFC 9457 problem details (`application/problem+json`), and the
//! JSON body extractor that turns every kind of bad body into one: malformed
//! JSON is 400, a body of the wrong shape or value is 422 naming the field,
//! an oversized body is 413.

use axum::body::Bytes;
use axum::extract::{FromRequest, Request};
use axum::http::{HeaderValue, StatusCode, header};
use axum::response::{IntoResponse, Response};
use patchwork_core::inverse::SettingsError;
use serde::Serialize;
use serde::de::DeserializeOwned;

#[derive(Debug, Clone, Serialize)]
pub struct Problem {
    #[serde(rename = "type")]
    pub kind: String,
    pub title: String,
    pub status: u16,
    pub detail: String,
    /// JSON path of the offending field, when one is to blame.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub field: Option<String>,
    #[serde(skip)]
    pub retry_after_s: Option<u64>,
}

impl Problem {
    pub fn new(status: StatusCode, detail: impl Into<String>) -> Problem {
        let title = status.canonical_reason().unwrap_or("Error").to_string();
        let slug = title.to_lowercase().replace(' ', "-");
        Problem {
            kind: format!("https://patchwork.dev/problems/{slug}"),
            title,
            status: status.as_u16(),
            detail: detail.into(),
            field: None,
            retry_after_s: None,
        }
    }

    pub fn field(mut self, field: impl Into<String>) -> Problem {
        self.field = Some(field.into());
        self
    }

    /// 422 naming the field.
    pub fn invalid(field: impl Into<String>, detail: impl Into<String>) -> Problem {
        Problem::new(StatusCode::UNPROCESSABLE_ENTITY, detail).field(field)
    }

    pub fn not_found(detail: impl Into<String>) -> Problem {
        Problem::new(StatusCode::NOT_FOUND, detail)
    }

    /// The server's own failure (never the user's input): logged in full,
    /// reported without internals.
    pub fn internal(error: impl std::fmt::Display) -> Problem {
        tracing::error!("internal error: {error}");
        Problem::new(
            StatusCode::INTERNAL_SERVER_ERROR,
            "internal error; it has been logged",
        )
    }
}

impl From<SettingsError> for Problem {
    /// A refused setting is the user's: 422 naming the field.
    fn from(error: SettingsError) -> Problem {
        Problem::invalid(error.field, error.reason)
    }
}

impl From<sqlx::Error> for Problem {
    /// A database that does not answer (restarting, unreachable) is 503 with
    /// `Retry-After`, so a client tries again; anything else is the server's
    /// own failure.
    fn from(error: sqlx::Error) -> Problem {
        if crate::service::store::unavailable(&error) {
            tracing::warn!("database unavailable: {error}");
            let mut problem = Problem::new(
                StatusCode::SERVICE_UNAVAILABLE,
                "the database does not answer; try again shortly",
            );
            problem.retry_after_s = Some(2);
            return problem;
        }
        Problem::internal(error)
    }
}

impl IntoResponse for Problem {
    fn into_response(self) -> Response {
        let status = StatusCode::from_u16(self.status).unwrap_or(StatusCode::INTERNAL_SERVER_ERROR);
        let body = serde_json::to_vec(&self).unwrap_or_default();
        let mut response = (status, body).into_response();
        let headers = response.headers_mut();
        headers.insert(
            header::CONTENT_TYPE,
            HeaderValue::from_static("application/problem+json"),
        );
        if let Some(seconds) = self.retry_after_s {
            headers.insert(header::RETRY_AFTER, HeaderValue::from(seconds));
        }
        if status == StatusCode::PAYLOAD_TOO_LARGE {
            // The rest of the body was not read: the connection cannot carry
            // another request, so tell the client not to reuse it.
            headers.insert(header::CONNECTION, HeaderValue::from_static("close"));
        }
        if status == StatusCode::UNAUTHORIZED {
            headers.insert(header::WWW_AUTHENTICATE, HeaderValue::from_static("Bearer"));
        }
        response
    }
}

/// A JSON request body, deserialised with the path of any offending field.
pub struct ApiJson<T>(pub T);

impl<S: Send + Sync, T: DeserializeOwned> FromRequest<S> for ApiJson<T> {
    type Rejection = Problem;

    async fn from_request(request: Request, state: &S) -> Result<Self, Problem> {
        let json = request
            .headers()
            .get(header::CONTENT_TYPE)
            .and_then(|v| v.to_str().ok())
            .is_some_and(|v| {
                let essence = v.split(';').next().unwrap_or("").trim();
                essence == "application/json" || essence.ends_with("+json")
            });
        if !json {
            return Err(Problem::new(
                StatusCode::UNSUPPORTED_MEDIA_TYPE,
                "send the body as application/json",
            )
            .field("Content-Type"));
        }
        let bytes = Bytes::from_request(request, state).await.map_err(|e| {
            if e.status() == StatusCode::PAYLOAD_TOO_LARGE {
                Problem::new(StatusCode::PAYLOAD_TOO_LARGE, "request body is too large")
            } else {
                Problem::new(StatusCode::BAD_REQUEST, e.body_text())
            }
        })?;
        parse_json(&bytes).map(ApiJson)
    }
}

/// Syntax errors are 400; a well-formed body of the wrong shape is 422 with
/// the field's path (`curve.points[3]`).
pub fn parse_json<T: DeserializeOwned>(bytes: &[u8]) -> Result<T, Problem> {
    let mut value: serde_json::Value = serde_json::from_slice(bytes).map_err(|e| {
        Problem::new(
            StatusCode::BAD_REQUEST,
            format!(
                "malformed JSON at line {} column {}: {e}",
                e.line(),
                e.column()
            ),
        )
    })?;
    if let Err(steps) = normalise(&mut value) {
        let field = path_of(steps);
        return Err(Problem::invalid(
            field.clone(),
            format!("{field}: null is not a value here; leave the field out for its default"),
        ));
    }
    serde_path_to_error::deserialize(value).map_err(|e| {
        let field = field_of(&e.path().to_string(), &e.inner().to_string());
        let detail = if field.is_empty() {
            e.inner().to_string()
        } else {
            format!("{field}: {}", e.inner())
        };
        Problem::invalid(field, detail)
    })
}

/// One step of a JSON path, kept only on the way out of a failed walk.
enum Step {
    Key(String),
    Index(usize),
}

/// Readies a request body for deserialising in one walk: a whole number
/// written with a fraction becomes the integer (JSON does not tell `12.0`
/// from `12`: a count field accepts it, a number field reads the same
/// value); a `null` is refused with its path, innermost step first (no
/// request field takes one: an absent field has its default, so a null is
/// a mistake to name rather than a silent default).
fn normalise(value: &mut serde_json::Value) -> Result<(), Vec<Step>> {
    use serde_json::Value;
    match value {
        Value::Null => Err(Vec::new()),
        Value::Number(n) if !(n.is_i64() || n.is_u64()) => {
            if let Some(x) = n.as_f64()
                && x.fract() == 0.0
                && x.abs() < 9.0e15
            {
                *value = Value::from(x as i64);
            }
            Ok(())
        }
        Value::Array(items) => items.iter_mut().enumerate().try_for_each(|(i, item)| {
            normalise(item).map_err(|mut path| {
                path.push(Step::Index(i));
                path
            })
        }),
        Value::Object(fields) => fields.iter_mut().try_for_each(|(key, item)| {
            normalise(item).map_err(|mut path| {
                path.push(Step::Key(key.clone()));
                path
            })
        }),
        _ => Ok(()),
    }
}

/// `curve.points[3]` from the steps of [`normalise`], innermost first.
fn path_of(steps: Vec<Step>) -> String {
    let mut path = String::new();
    for step in steps.into_iter().rev() {
        match step {
            Step::Key(key) if path.is_empty() => path = key,
            Step::Key(key) => path = format!("{path}.{key}"),
            Step::Index(i) => path = format!("{path}[{i}]"),
        }
    }
    path
}

/// The JSON path serde blames, completed with the field a "missing field"
/// message names (serde reports that one at the parent).
pub fn field_of(path: &str, message: &str) -> String {
    let parent = if path == "." { "" } else { path };
    let named = message
        .strip_prefix("missing field `")
        .and_then(|rest| rest.split('`').next());
    match (parent, named) {
        ("", Some(name)) => name.to_string(),
        (parent, Some(name)) => format!("{parent}.{name}"),
        (parent, None) => parent.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::service::request::JobRequest;

    #[test]
    fn a_whole_number_with_a_fraction_counts_and_a_null_is_named() {
        let job: JobRequest =
            parse_json(br#"{"curve": {"preset": "arc", "samples": 400.0}}"#).unwrap();
        assert_eq!(job.curve.samples, Some(400));
        let fraction = parse_json::<JobRequest>(br#"{"curve": {"preset": "arc", "samples": 4.5}}"#);
        assert_eq!(
            fraction.unwrap_err().field.as_deref(),
            Some("curve.samples")
        );
        let null = parse_json::<JobRequest>(
            br#"{"curve": {"preset": "arc"}, "bounds": {"w_min_mm": null}}"#,
        );
        let problem = null.unwrap_err();
        assert_eq!(problem.field.as_deref(), Some("bounds.w_min_mm"));
        let deep = parse_json::<JobRequest>(br#"{"curve": {"points": [[0, 0, 0], [1, null, 0]]}}"#);
        assert_eq!(
            deep.unwrap_err().field.as_deref(),
            Some("curve.points[1][1]")
        );
        assert!(problem.detail.contains("null"), "{}", problem.detail);
    }
}
