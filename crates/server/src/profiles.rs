//! The profile editor's endpoints: a machine profile's TOML text, checked by the motion
//! crate's own validation (its key and message go back to the page), and a checked profile
//! put on the virtual machine. Profiles the page saves live in the job folder.

use crate::files::path_in;
use crate::AppState;
use axum::body::Bytes;
use axum::extract::{Path, State};
use axum::http::StatusCode;
use axum::response::{IntoResponse, Response};
use axum::Json;
use oficina_app::profile::{Profile, BUNDLED};
use serde_json::json;
use std::sync::Arc;

fn refused(status: StatusCode, key: &str, message: String) -> Response {
    (
        status,
        Json(json!({"ok": false, "key": key, "error": message})),
    )
        .into_response()
}

/// A bundled profile's text (`GET /api/profiles/grbl-router`).
pub async fn text(Path(name): Path<String>) -> Response {
    match BUNDLED.iter().find(|(n, _)| *n == name) {
        Some((_, t)) => t.to_string().into_response(),
        None => refused(
            StatusCode::NOT_FOUND,
            "",
            format!("no bundled profile named {name}"),
        ),
    }
}

fn parse(body: &Bytes) -> Result<Profile, Response> {
    let text = std::str::from_utf8(body).map_err(|_| {
        refused(
            StatusCode::BAD_REQUEST,
            "",
            "the profile is not UTF-8 text".into(),
        )
    })?;
    Profile::parse(text, "profile")
        .map_err(|e| refused(StatusCode::BAD_REQUEST, &e.key, e.message.clone()))
}

fn summary(p: &Profile) -> serde_json::Value {
    json!({"ok": true, "name": p.name, "travel": p.travel})
}

/// Validates without using (`POST /api/profiles/check`).
pub async fn check(body: Bytes) -> Response {
    match parse(&body) {
        Ok(p) => Json(summary(&p)).into_response(),
        Err(r) => r,
    }
}

/// Validates, saves as `profile-NAME.toml` in the job folder and connects the virtual
/// machine to it (refused while the machine is busy).
pub async fn use_profile(State(st): State<Arc<AppState>>, body: Bytes) -> Response {
    let p = match parse(&body) {
        Ok(p) => p,
        Err(r) => return r,
    };
    let stem: String = p
        .name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '-'
            }
        })
        .take(80)
        .collect();
    let file = format!("profile-{stem}.toml");
    let path = match path_in(&st.config.job_dir, &file) {
        Ok(p) => p,
        Err(e) => return refused(StatusCode::BAD_REQUEST, "name", e),
    };
    if let Err(e) = tokio::fs::write(&path, &body).await {
        return refused(StatusCode::BAD_REQUEST, "", format!("{file}: {e}"));
    }
    let uri = format!("virtual:{}", path.display());
    let st2 = st.clone();
    let u = uri.clone();
    match tokio::task::spawn_blocking(move || st2.connect(&u)).await {
        Ok(Ok(())) => {
            let mut v = summary(&p);
            v["uri"] = json!(uri);
            Json(v).into_response()
        }
        Ok(Err(e)) => refused(StatusCode::CONFLICT, "", e),
        Err(e) => refused(StatusCode::INTERNAL_SERVER_ERROR, "", e.to_string()),
    }
}
