//! `/v1/balloons`: a lab's named balloon profiles, each API key its own —
//! the uninflated balloon and the patch, their materials typically from a
//! calibration (a calibration job's `save_as` stores one). A job request
//! names one by `balloon_profile`; the profile is read when the job is
//! submitted and written into its spec, so a later change to the profile
//! never changes a job.

use axum::Extension;
use axum::Json;
use axum::extract::{Path, State};
use axum::http::StatusCode;
use axum::response::{IntoResponse, Response};
use patchwork_core::design::Design;
use serde_json::{Value, json};

use super::auth::Owner;
use super::problem::{ApiJson, Problem};
use super::profile::Profile;
use super::request::validate_design;
use super::state::AppState;
use super::store::ProfileRow;

/// The profile's balloon and patch checked as a design's, the field named
/// as the profile names it.
fn validate(profile: &Profile) -> Result<(), Problem> {
    let design = Design {
        balloon: profile.balloon.clone(),
        patch: profile.patch.clone(),
        ..Design::reference(Vec::new())
    };
    Ok(validate_design(&design, "")?)
}

/// Most characters in a profile's name.
const NAME_MAX: usize = 64;

/// A profile's name: 1–64 letters, digits, `.`, `_` or `-`, starting with
/// a letter or digit (it is a path segment and a file name).
pub fn check_name(name: &str, field: &str) -> Result<(), Problem> {
    let good = (1..=NAME_MAX).contains(&name.len())
        && name.starts_with(|c: char| c.is_ascii_alphanumeric())
        && name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || "._-".contains(c));
    if good {
        return Ok(());
    }
    Err(Problem::invalid(
        field,
        format!(
            "a balloon profile's name is 1–{NAME_MAX} letters, digits, `.`, `_` or `-`, starting with a letter or digit"
        ),
    ))
}

/// The owner's profile `name`, for a request's `field`; a name the owner
/// has no profile of is refused naming the field.
pub async fn resolve(
    state: &AppState,
    owner: &Owner,
    name: &str,
    field: &str,
) -> Result<Profile, Problem> {
    check_name(name, field)?;
    let Some(row) = state.store.profile(owner.stored(), name).await? else {
        return Err(Problem::invalid(
            field,
            format!("no balloon profile named `{name}`: PUT /v1/balloons/{name} first"),
        ));
    };
    serde_json::from_str(&row.profile).map_err(Problem::internal)
}

fn view(row: &ProfileRow) -> Result<Value, Problem> {
    let mut view: Value = serde_json::from_str(&row.profile).map_err(Problem::internal)?;
    view["name"] = json!(row.name);
    view["source_job"] = json!(row.source_job);
    view["created_at"] = json!(row.created_at);
    view["updated_at"] = json!(row.updated_at);
    view["links"] = json!({"self": format!("/v1/balloons/{}", row.name)});
    Ok(view)
}

async fn owned(state: &AppState, owner: &Owner, name: &str) -> Result<ProfileRow, Problem> {
    let missing = || Problem::not_found(format!("no balloon profile named `{name}`"));
    if check_name(name, "name").is_err() {
        return Err(missing());
    }
    (state.store.profile(owner.stored(), name).await?).ok_or_else(missing)
}

/// `PUT /v1/balloons/{name}`: 201 for a new profile, 200 for one replaced.
pub async fn put(
    State(state): State<AppState>,
    Extension(owner): Extension<Owner>,
    Path(name): Path<String>,
    ApiJson(profile): ApiJson<Profile>,
) -> Result<Response, Problem> {
    check_name(&name, "name")?;
    validate(&profile)?;
    let text = serde_json::to_string(&profile).map_err(Problem::internal)?;
    let created = (state.store)
        .put_profile(owner.stored(), &name, &text, None)
        .await?;
    let row = owned(&state, &owner, &name).await?;
    let status = if created {
        StatusCode::CREATED
    } else {
        StatusCode::OK
    };
    Ok((status, Json(view(&row)?)).into_response())
}

pub async fn get(
    State(state): State<AppState>,
    Extension(owner): Extension<Owner>,
    Path(name): Path<String>,
) -> Result<Json<Value>, Problem> {
    Ok(Json(view(&owned(&state, &owner, &name).await?)?))
}

pub async fn list(
    State(state): State<AppState>,
    Extension(owner): Extension<Owner>,
) -> Result<Json<Value>, Problem> {
    let rows = state.store.profiles(owner.stored()).await?;
    let balloons = rows.iter().map(view).collect::<Result<Vec<_>, _>>()?;
    Ok(Json(json!({ "balloons": balloons })))
}

pub async fn delete(
    State(state): State<AppState>,
    Extension(owner): Extension<Owner>,
    Path(name): Path<String>,
) -> Result<StatusCode, Problem> {
    owned(&state, &owner, &name).await?;
    state.store.delete_profile(owner.stored(), &name).await?;
    Ok(StatusCode::NO_CONTENT)
}
