//! API keys: when keys are configured, every `/v1` route needs
//! `Authorization: Bearer <key>`, and a key sees only its own jobs.

use axum::extract::{Request, State};
use axum::http::{StatusCode, header};
use axum::middleware::Next;
use axum::response::{IntoResponse, Response};

use super::config::owner_of;
use super::problem::Problem;
use super::state::AppState;

/// Who is asking: the key's digest, or `None` when authentication is off
/// (everyone sees every job).
#[derive(Debug, Clone)]
pub struct Owner(pub Option<String>);

impl Owner {
    /// The value stored in `jobs.owner`.
    pub fn stored(&self) -> &str {
        self.0.as_deref().unwrap_or("")
    }

    /// The filter for reads: `None` sees everything.
    pub fn filter(&self) -> Option<&str> {
        self.0.as_deref()
    }
}

pub async fn require_key(
    State(state): State<AppState>,
    mut request: Request,
    next: Next,
) -> Response {
    if !state.config.auth_enabled() {
        request.extensions_mut().insert(Owner(None));
        return next.run(request).await;
    }
    let key = request
        .headers()
        .get(header::AUTHORIZATION)
        .and_then(|v| v.to_str().ok())
        .and_then(|v| v.strip_prefix("Bearer "))
        .map(str::trim);
    let Some(key) = key else {
        return Problem::new(
            StatusCode::UNAUTHORIZED,
            "send `Authorization: Bearer <API key>`",
        )
        .field("Authorization")
        .into_response();
    };
    let owner = owner_of(key);
    if !state.config.owners.contains(&owner) {
        return Problem::new(StatusCode::UNAUTHORIZED, "unknown API key")
            .field("Authorization")
            .into_response();
    }
    request.extensions_mut().insert(Owner(Some(owner)));
    next.run(request).await
}
