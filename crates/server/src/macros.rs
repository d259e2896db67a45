//! The macros' endpoints: the list kept as `macros.json` in the job folder, read and saved
//! (checked by the application layer first: names, sizes, parameters).

use crate::files::path_in;
use crate::AppState;
use axum::body::Bytes;
use axum::extract::State;
use axum::http::StatusCode;
use axum::response::{IntoResponse, Response};
use axum::Json;
use oficina_app::{check_macros, Macro, MACROS_FILE};
use serde_json::json;
use std::sync::Arc;

fn parse(text: &[u8]) -> Result<Vec<Macro>, String> {
    let list: Vec<Macro> = serde_json::from_slice(text)
        .map_err(|e| format!("{MACROS_FILE}: a list of {{\"name\", \"text\"}} ({e})"))?;
    check_macros(&list).map_err(|e| e.to_string())?;
    Ok(list)
}

/// The macros saved in the job folder (none when no file was saved).
pub(crate) fn saved_macros(st: &AppState) -> Result<Vec<Macro>, String> {
    let path = path_in(&st.config.job_dir, MACROS_FILE)?;
    match std::fs::read(&path) {
        Ok(b) => parse(&b),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(Vec::new()),
        Err(e) => Err(format!("{MACROS_FILE}: {e}")),
    }
}

/// The text of the saved macro `name`.
pub(crate) fn macro_text(st: &AppState, name: &str) -> Result<String, String> {
    saved_macros(st)?
        .into_iter()
        .find(|m| m.name.trim() == name.trim())
        .map(|m| m.text)
        .ok_or_else(|| format!("no macro named {name:?} (save it first)"))
}

fn refused(status: StatusCode, message: String) -> Response {
    (status, Json(json!({"ok": false, "error": message}))).into_response()
}

/// `GET /api/macros`: the saved list.
pub(crate) async fn list(State(st): State<Arc<AppState>>) -> Response {
    match saved_macros(&st) {
        Ok(m) => Json(json!({"ok": true, "macros": m})).into_response(),
        Err(e) => refused(StatusCode::CONFLICT, e),
    }
}

/// `PUT /api/macros`: checks and saves the whole list.
pub(crate) async fn save(State(st): State<Arc<AppState>>, body: Bytes) -> Response {
    let list = match parse(&body) {
        Ok(l) => l,
        Err(e) => return refused(StatusCode::BAD_REQUEST, e),
    };
    let path = match path_in(&st.config.job_dir, MACROS_FILE) {
        Ok(p) => p,
        Err(e) => return refused(StatusCode::BAD_REQUEST, e),
    };
    let text = serde_json::to_string_pretty(&list).unwrap_or_default();
    if let Err(e) = tokio::fs::write(&path, text).await {
        return refused(StatusCode::BAD_REQUEST, format!("{MACROS_FILE}: {e}"));
    }
    st.say(&format!("saved {} macros", list.len()));
    Json(json!({"ok": true, "macros": list})).into_response()
}
