//! The route table. The router is built from it, and a test checks that it and
//! the paths and methods of `openapi.yaml` are the same set.

use axum::Router;
use axum::handler::Handler;
use axum::http::Method;
use axum::routing::{MethodFilter, MethodRouter, on};

use super::state::AppState;
use super::{balloons, calibrations, compare, events, jobs, ops, quick};

/// Whether a route sits behind the API key check.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Access {
    Open,
    Keyed,
}

pub struct Route {
    pub method: &'static str,
    pub path: &'static str,
    pub access: Access,
    pub handler: MethodRouter<AppState>,
}

/// One route; the method string is what the router serves (and what the
/// OpenAPI test compares).
fn route<H, T>(method: &'static str, path: &'static str, access: Access, handler: H) -> Route
where
    H: Handler<T, AppState>,
    T: 'static,
{
    let filter = Method::from_bytes(method.as_bytes())
        .ok()
        .and_then(|m| MethodFilter::try_from(m).ok())
        .unwrap_or_else(|| panic!("route table: unknown method {method}"));
    Route {
        method,
        path,
        access,
        handler: on(filter, handler),
    }
}

pub fn table() -> Vec<Route> {
    use Access::{Keyed, Open};
    vec![
        route("GET", "/healthz", Open, ops::healthz),
        route("GET", "/readyz", Open, ops::readyz),
        route("GET", "/metrics", Open, ops::metrics),
        route("GET", "/openapi.yaml", Open, ops::openapi),
        route("POST", "/v1/jobs", Keyed, jobs::create),
        route("GET", "/v1/jobs", Keyed, jobs::list),
        route("GET", "/v1/jobs/{id}", Keyed, jobs::get),
        route("DELETE", "/v1/jobs/{id}", Keyed, jobs::delete),
        route("POST", "/v1/jobs/{id}/cancel", Keyed, jobs::cancel),
        route("GET", "/v1/jobs/{id}/events", Keyed, events::stream),
        route("GET", "/v1/jobs/{id}/iterations", Keyed, jobs::iterations),
        route("GET", "/v1/jobs/{id}/result", Keyed, jobs::result),
        route("GET", "/v1/jobs/{id}/files/{name}", Keyed, jobs::file),
        route(
            "POST",
            "/v1/jobs/{id}/compare",
            Keyed,
            compare::job_compare_route,
        ),
        route(
            "POST",
            "/v1/jobs/{id}/compare/scan",
            Keyed,
            compare::job_scan_route,
        ),
        route("POST", "/v1/compare", Keyed, compare::compare_route),
        route("POST", "/v1/calibrations", Keyed, calibrations::create),
        route("GET", "/v1/balloons", Keyed, balloons::list),
        route("GET", "/v1/balloons/{name}", Keyed, balloons::get),
        route("PUT", "/v1/balloons/{name}", Keyed, balloons::put),
        route("DELETE", "/v1/balloons/{name}", Keyed, balloons::delete),
        route("POST", "/v1/curve", Keyed, quick::curve_route),
        route("POST", "/v1/ksa", Keyed, quick::ksa_route),
        route("POST", "/v1/simulate", Keyed, quick::simulate_route),
        route("GET", "/v1/presets", Keyed, quick::presets),
    ]
}

/// The routes of one access level, methods of a path merged.
pub fn router(access: Access) -> Router<AppState> {
    let mut merged: Vec<(&'static str, MethodRouter<AppState>)> = Vec::new();
    for r in table().into_iter().filter(|r| r.access == access) {
        tracing::debug!(method = r.method, path = r.path, ?access, "route");
        match merged.iter_mut().find(|(p, _)| *p == r.path) {
            Some((_, handler)) => *handler = std::mem::take(handler).merge(r.handler),
            None => merged.push((r.path, r.handler)),
        }
    }
    merged
        .into_iter()
        .fold(Router::new(), |router, (path, handler)| {
            router.route(path, handler)
        })
}

#[cfg(test)]
mod tests {
    use std::collections::BTreeSet;

    /// Served routes and the spec's paths × methods are the same set.
    #[test]
    fn routes_match_the_openapi_document() {
        let spec: serde_json::Value = serde_norway::from_str(super::ops::OPENAPI).unwrap();
        let mut documented = BTreeSet::new();
        for (path, item) in spec["paths"].as_object().unwrap() {
            for method in item.as_object().unwrap().keys() {
                if ["get", "post", "put", "patch", "delete"].contains(&method.as_str()) {
                    documented.insert((method.to_uppercase(), path.clone()));
                }
            }
        }
        let served: BTreeSet<(String, String)> = super::table()
            .iter()
            .map(|r| (r.method.to_string(), r.path.to_string()))
            .collect();
        assert_eq!(served, documented);
    }
}
