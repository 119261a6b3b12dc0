//! Oversized bodies are refused from their `Content-Length`, before a handler
//! sees them, in a way every client can read:
//!
//! - A client that sends `Expect: 100-continue` (curl does for large uploads)
//!   gets the 413 problem at once and uploads nothing: hyper sends
//!   `100 Continue` only when something starts reading the body.
//! - Any other client is still writing its body when the answer is ready. If
//!   the server answered and closed with unread bytes in its socket, the
//!   kernel would reset the connection and the client could lose the answer
//!   (it happened in CI). So the declared body is read and discarded first
//!   ("lingering close"), up to [`DRAIN_FACTOR`] × the limit and
//!   [`DRAIN_TIME`]; past those the answer goes out regardless.
//!
//! Bodies without a declared length (chunked) are cut off at the limit while
//! being read ([`axum::extract::DefaultBodyLimit`]); that path does not drain.

use std::time::Duration;

use axum::extract::{Request, State};
use axum::http::{StatusCode, header};
use axum::middleware::Next;
use axum::response::{IntoResponse, Response};
use futures_util::StreamExt;

use super::problem::Problem;
use super::state::AppState;

/// Routes ending so take a scan, up to `scan_limit_bytes` instead.
pub const SCAN_UPLOAD: &str = "/compare/scan";

/// Declared bodies up to this many times the limit are drained before the 413.
pub const DRAIN_FACTOR: u64 = 8;
/// The longest a refused body is drained.
pub const DRAIN_TIME: Duration = Duration::from_secs(10);

pub async fn refuse_declared_oversize(
    State(state): State<AppState>,
    request: Request,
    next: Next,
) -> Response {
    let limit = match request.uri().path().ends_with(SCAN_UPLOAD) {
        true => state.config.scan_limit_bytes,
        false => state.config.body_limit_bytes,
    } as u64;
    let headers = request.headers();
    let declared = headers
        .get(header::CONTENT_LENGTH)
        .and_then(|v| v.to_str().ok())
        .and_then(|v| v.trim().parse::<u64>().ok());
    let Some(length) = declared.filter(|&length| length > limit) else {
        return next.run(request).await;
    };
    let expects_continue = headers
        .get(header::EXPECT)
        .and_then(|v| v.to_str().ok())
        .is_some_and(|v| v.trim().eq_ignore_ascii_case("100-continue"));
    if !expects_continue && length <= DRAIN_FACTOR.saturating_mul(limit) {
        let mut body = request.into_body().into_data_stream();
        let drain = async { while let Some(Ok(_)) = body.next().await {} };
        // A client too slow to send its body in time gets the answer anyway.
        let _ = tokio::time::timeout(DRAIN_TIME, drain).await;
    }
    Problem::new(
        StatusCode::PAYLOAD_TOO_LARGE,
        format!("request body of {length} bytes is over the limit of {limit} bytes"),
    )
    .into_response()
}
