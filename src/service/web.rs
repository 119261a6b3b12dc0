//! The web app at `/`: the files of `web/static`, embedded in the binary at
//! build time (no CDN, no files beside the binary) and served with cache
//! validators. The page is a client of the public API alone.
//!
//! Caching: the versioned library folder (`vendor/three-VERSION/`) never
//! changes under its name and is cached for a year; the app's own files are
//! revalidated on every load (`no-cache` with an `ETag`), so a new binary's
//! page is seen at once.

use std::sync::OnceLock;

use axum::Router;
use axum::extract::Path;
use axum::http::{HeaderMap, HeaderValue, StatusCode, header};
use axum::response::{IntoResponse, Response};
use axum::routing::get;
use sha2::{Digest, Sha256};

use super::problem::Problem;
use super::state::AppState;

macro_rules! assets {
    ($($path:literal),* $(,)?) => {
        &[$(($path, include_bytes!(concat!(env!("CARGO_MANIFEST_DIR"), "/web/static/", $path)))),*]
    };
}

/// Every file of `web/static` (a test checks the folder and this list agree).
const ASSETS: &[(&str, &[u8])] = assets![
    "index.html",
    "app.css",
    "js/api.js",
    "js/events.js",
    "js/main.js",
    "js/curve.js",
    "js/submit.js",
    "js/watch.js",
    "js/result.js",
    "js/compare.js",
    "js/calibration.js",
    "js/calibrate_form.js",
    "js/jobs.js",
    "js/plot.js",
    "js/unrolled.js",
    "js/view3d.js",
    "js/dom.js",
    "js/align.js",
    "vendor/three-0.187.0/LICENSE",
    "vendor/three-0.187.0/OrbitControls.js",
    "vendor/three-0.187.0/three.core.js",
    "vendor/three-0.187.0/three.module.js",
];

/// The page's routes: `/` and `/assets/{path}`, open (the page asks for a
/// key itself when the API needs one).
pub fn router() -> Router<AppState> {
    Router::new()
        .route("/", get(|headers: HeaderMap| async move { serve("index.html", &headers) }))
        .route(
            "/assets/{*path}",
            get(|Path(path): Path<String>, headers: HeaderMap| async move {
                serve(&path, &headers)
            }),
        )
}

fn serve(path: &str, headers: &HeaderMap) -> Response {
    let Some(index) = ASSETS.iter().position(|(name, _)| *name == path) else {
        return Problem::not_found("no such file").into_response();
    };
    let body = ASSETS[index].1;
    let etag = &etags()[index];
    let cache = if path.starts_with("vendor/three-") {
        "public, max-age=31536000, immutable"
    } else {
        "no-cache"
    };
    let fresh = headers
        .get(header::IF_NONE_MATCH)
        .and_then(|v| v.to_str().ok())
        .is_some_and(|tags| tags.split(',').any(|t| t.trim() == etag));
    let common = [
        (header::ETAG, HeaderValue::from_str(etag).expect("hex")),
        (header::CACHE_CONTROL, HeaderValue::from_static(cache)),
        (
            header::X_CONTENT_TYPE_OPTIONS,
            HeaderValue::from_static("nosniff"),
        ),
    ];
    if fresh {
        return (StatusCode::NOT_MODIFIED, common).into_response();
    }
    let kind = HeaderValue::from_static(content_type(path));
    (common, [(header::CONTENT_TYPE, kind)], body).into_response()
}

/// `"<first 16 hex digits of the SHA-256>"` of each asset, computed once.
fn etags() -> &'static [String] {
    static ETAGS: OnceLock<Vec<String>> = OnceLock::new();
    ETAGS.get_or_init(|| {
        ASSETS
            .iter()
            .map(|(_, body)| {
                let digest = Sha256::digest(body);
                let hex: String = digest[..8].iter().map(|b| format!("{b:02x}")).collect();
                format!("\"{hex}\"")
            })
            .collect()
    })
}

fn content_type(path: &str) -> &'static str {
    match path.rsplit('.').next() {
        Some("html") => "text/html; charset=utf-8",
        Some("css") => "text/css; charset=utf-8",
        Some("js") => "text/javascript; charset=utf-8",
        Some("svg") => "image/svg+xml",
        _ => "text/plain; charset=utf-8",
    }
}

#[cfg(test)]
mod tests {
    use std::collections::BTreeSet;
    use std::path::Path;

    fn files_under(dir: &Path, root: &Path, out: &mut BTreeSet<String>) {
        for entry in std::fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                files_under(&path, root, out);
            } else {
                let name = path.strip_prefix(root).unwrap().to_string_lossy();
                out.insert(name.replace('\\', "/"));
            }
        }
    }

    /// The embedded list and `web/static` hold the same files.
    #[test]
    fn every_static_file_is_embedded() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("web/static");
        let mut on_disk = BTreeSet::new();
        files_under(&root, &root, &mut on_disk);
        let embedded: BTreeSet<String> = super::ASSETS.iter().map(|(n, _)| n.to_string()).collect();
        assert_eq!(embedded, on_disk);
    }

    /// The vendored three.js is the version web/package-lock.json pins, and
    /// index.html's import map points at it.
    #[test]
    fn vendored_library_is_the_locked_version() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("web");
        let lock: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(root.join("package-lock.json")).unwrap())
                .unwrap();
        let version = lock["packages"]["node_modules/three"]["version"]
            .as_str()
            .unwrap();
        let folder = format!("vendor/three-{version}/");
        assert!(super::ASSETS.iter().any(|(n, _)| n.starts_with(&folder)));
        let module = super::ASSETS
            .iter()
            .find(|(n, _)| *n == format!("{folder}three.core.js"))
            .unwrap();
        let revision = version.split('.').nth(1).unwrap();
        let text = String::from_utf8_lossy(module.1);
        assert!(text.contains(&format!("const REVISION = '{revision}';")));
        let index = std::fs::read_to_string(root.join("static/index.html")).unwrap();
        assert!(index.contains(&format!("/assets/{folder}three.module.js")));
    }
}
