//! `patchwork serve`: the HTTP design service. Jobs live in SQLite; workers
//! run the design pipeline on blocking threads; progress reaches clients as
//! server-sent events. See ARCHITECTURE.md for the request and job lifecycles.

mod auth;
mod balloons;
mod body_limit;
mod calibrations;
mod compare;
mod config;
pub mod copy_jobs;
mod events;
mod job_state;
mod job_view;
mod jobs;
mod ops;
mod problem;
mod profile;
mod quick;
mod relay;
pub(crate) mod request;
mod routes;
pub(crate) mod spec;
mod state;
mod store;
mod submit;
mod upgrade;
mod web;
mod worker;

use std::sync::Arc;
use std::sync::atomic::Ordering;
use std::time::Duration;

use anyhow::{Context, Result};
use axum::Router;
use axum::extract::DefaultBodyLimit;
use axum::http::{HeaderValue, Method, StatusCode};
use axum::response::IntoResponse;
use tower_http::cors::{AllowOrigin, Any, CorsLayer};
use tower_http::trace::TraceLayer;

use config::Config;
pub use config::ServeArgs;
pub use copy_jobs::CopyJobsArgs;
use problem::Problem;
use routes::Access;
use state::{AppState, Shared};

/// How long a graceful shutdown waits for running jobs to checkpoint.
const SHUTDOWN_GRACE: Duration = Duration::from_secs(20);

pub fn run(args: ServeArgs) -> Result<()> {
    let config = Config::resolve(&args)?;
    tracing_subscriber::fmt()
        .with_env_filter(
            tracing_subscriber::EnvFilter::try_from_default_env()
                .unwrap_or_else(|_| "info,sqlx=warn,tower_http=info".into()),
        )
        .with_writer(std::io::stderr)
        .with_ansi(std::io::IsTerminal::is_terminal(&std::io::stderr()))
        .init();
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .build()
        .context("starting the async runtime")?;
    runtime.block_on(serve(config))
}

async fn serve(config: Config) -> Result<()> {
    let store = config
        .db
        .open()
        .await
        .with_context(|| format!("opening the database {}", config.db))?;
    let derived = upgrade::derive_specs(store.as_ref()).await?;
    if derived != upgrade::Derived::default() {
        tracing::info!(
            specs = derived.specs,
            failed = derived.failed,
            "jobs stored before job specs given theirs"
        );
    }
    let requeued = store.requeue_orphans().await?;
    if requeued > 0 {
        tracing::info!(
            jobs = requeued,
            "interrupted jobs queued to resume from their checkpoints"
        );
    }
    let listener = tokio::net::TcpListener::bind(config.addr)
        .await
        .with_context(|| format!("cannot listen on {}", config.addr))?;
    let addr = listener.local_addr()?;
    let state: AppState = Arc::new(Shared {
        store,
        hub: Default::default(),
        running: Default::default(),
        wake: Default::default(),
        shutting_down: Default::default(),
        counters: Default::default(),
        caches: Default::default(),
        config,
    });
    let app = app(state.clone());
    let workers = worker::start(&state);
    let _relay = relay::start(&state);
    // Scripts (and the tests) read the address from the first line of stdout.
    println!("listening on http://{addr}");
    tracing::info!(%addr, workers = state.config.workers, auth = state.config.auth_enabled(), "serving");
    let shutdown_state = state.clone();
    axum::serve(listener, app)
        .with_graceful_shutdown(async move {
            shutdown_signal().await;
            tracing::info!("shutting down: checkpointing running jobs");
            shutdown_state.shutting_down.store(true, Ordering::Relaxed);
            worker::stop_all(&shutdown_state);
            shutdown_state.wake.notify_waiters();
        })
        .await?;
    let all = futures_util::future::join_all(workers);
    if tokio::time::timeout(SHUTDOWN_GRACE, all).await.is_err() {
        tracing::warn!("workers did not stop in time; their jobs resume from the last checkpoint");
    }
    Ok(())
}

fn app(state: AppState) -> Router {
    let keyed = routes::router(Access::Keyed).route_layer(axum::middleware::from_fn_with_state(
        state.clone(),
        auth::require_key,
    ));
    let body_limit = state.config.body_limit_bytes;
    let cors = cors(&state.config);
    routes::router(Access::Open)
        .merge(keyed)
        .merge(web::router())
        .fallback(|| async { Problem::not_found("no such route").into_response() })
        .method_not_allowed_fallback(|| async {
            Problem::new(
                StatusCode::METHOD_NOT_ALLOWED,
                "method not allowed on this route",
            )
            .into_response()
        })
        .layer(DefaultBodyLimit::max(body_limit))
        .layer(axum::middleware::from_fn_with_state(
            state.clone(),
            body_limit::refuse_declared_oversize,
        ))
        .layer(TraceLayer::new_for_http())
        .layer(cors)
        .with_state(state)
}

fn cors(config: &Config) -> CorsLayer {
    let layer = CorsLayer::new()
        .allow_methods([Method::GET, Method::POST, Method::DELETE])
        .allow_headers(Any)
        .expose_headers([axum::http::header::LOCATION]);
    if config.cors_origins.iter().any(|o| o == "*") {
        layer.allow_origin(Any)
    } else {
        let origins: Vec<HeaderValue> = config
            .cors_origins
            .iter()
            .filter_map(|o| HeaderValue::from_str(o).ok())
            .collect();
        layer.allow_origin(AllowOrigin::list(origins))
    }
}

async fn shutdown_signal() {
    let ctrl_c = async {
        let _ = tokio::signal::ctrl_c().await;
    };
    #[cfg(unix)]
    let terminate = async {
        match tokio::signal::unix::signal(tokio::signal::unix::SignalKind::terminate()) {
            Ok(mut s) => {
                s.recv().await;
            }
            Err(_) => std::future::pending::<()>().await,
        }
    };
    #[cfg(not(unix))]
    let terminate = std::future::pending::<()>();
    tokio::select! {
        _ = ctrl_c => {},
        _ = terminate => {},
    }
}
