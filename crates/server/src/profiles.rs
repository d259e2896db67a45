//! The profile editor's endpoints: a machine profile's TOML text, checked by the motion
//! crate's own validation (its key and message go back to the page), and a checked profile
//! put on the virtual machine; the tool table, read by the interpreter's parser. Both are
//! saved in the job folder.

use crate::files::path_in;
use crate::AppState;
use axum::body::Bytes;
use axum::extract::{Path, State};
use axum::http::StatusCode;
use axum::response::{IntoResponse, Response};
use axum::Json;
use oficina_app::profile::{Profile, BUNDLED};
use oficina_app::{check_tool_table, parse_tool_table, TOOL_TABLE_FILE};
use oficina_gcode::ToolTable;
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
pub(crate) async fn text(Path(name): Path<String>) -> Response {
    match BUNDLED.iter().find(|(n, _)| *n == name) {
        Some((_, t)) => t.to_string().into_response(),
        None => refused(
            StatusCode::NOT_FOUND,
            "",
            format!("no bundled profile named {name}"),
        ),
    }
}

fn parse(body: &Bytes) -> Result<Profile, Box<Response>> {
    let text = std::str::from_utf8(body).map_err(|_| {
        Box::new(refused(
            StatusCode::BAD_REQUEST,
            "",
            "the profile is not UTF-8 text".into(),
        ))
    })?;
    Profile::parse(text, "profile")
        .map_err(|e| Box::new(refused(StatusCode::BAD_REQUEST, &e.key, e.message.clone())))
}

fn summary(p: &Profile) -> serde_json::Value {
    json!({"ok": true, "name": p.name, "travel": p.travel})
}

/// Validates without using (`POST /api/profiles/check`).
pub(crate) async fn check(body: Bytes) -> Response {
    match parse(&body) {
        Ok(p) => Json(summary(&p)).into_response(),
        Err(r) => *r,
    }
}

/// Validates, saves as `profile-NAME.toml` in the job folder and connects the virtual
/// machine to it (refused while the machine is busy).
pub(crate) async fn use_profile(State(st): State<Arc<AppState>>, body: Bytes) -> Response {
    let p = match parse(&body) {
        Ok(p) => p,
        Err(r) => return *r,
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

/// A machine profile a request names: a bundled profile, or a profile file in the job folder
/// (the editor saves them there). Anything else, a path elsewhere on this computer above
/// all, is refused: a request never reads files outside the job folder. Gives the spec to
/// resolve (the bundled name, or the file's full path).
pub(crate) fn profile_spec(st: &AppState, spec: &str) -> Result<String, String> {
    if BUNDLED.iter().any(|(n, _)| *n == spec) {
        return Ok(spec.to_string());
    }
    let names: Vec<&str> = BUNDLED.iter().map(|(n, _)| *n).collect();
    let refused = || {
        format!(
            "profile {spec:?}: neither a bundled profile ({}) nor a profile file in the job folder",
            names.join(", ")
        )
    };
    match path_in(&st.config.job_dir, spec) {
        Ok(p) if p.is_file() => Ok(p.display().to_string()),
        _ => Err(refused()),
    }
}

/// A machine URI a page asks to connect to: firmware addresses as they are; a virtual
/// machine's profile only as [`profile_spec`] allows.
pub(crate) fn machine_uri(st: &AppState, uri: &str) -> Result<String, String> {
    if oficina_app::is_firmware(uri) {
        return Ok(uri.to_string());
    }
    let name = match uri.strip_prefix("virtual") {
        Some("") => return Ok(uri.to_string()),
        Some(rest) => rest.strip_prefix(':').ok_or_else(|| {
            format!("machine {uri:?}: virtual, virtual:PROFILE, grbl:PORT or tcp://HOST:PORT")
        })?,
        None => uri,
    };
    // A path the editor saved is in the job folder already: named by its file name there.
    let in_jobs = std::path::Path::new(name)
        .strip_prefix(&st.config.job_dir)
        .ok()
        .and_then(|p| p.to_str())
        .unwrap_or(name);
    profile_spec(st, in_jobs).map(|s| format!("virtual:{s}"))
}

/// The tool table saved in the job folder, as the check and the virtual machine take it
/// (empty when none was saved). A table put there by other means and unreadable is named.
pub(crate) fn saved_tools(st: &AppState) -> Result<ToolTable, String> {
    let path = path_in(&st.config.job_dir, TOOL_TABLE_FILE)?;
    let text = match std::fs::read(&path) {
        Ok(b) => b,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(ToolTable::default()),
        Err(e) => return Err(format!("{TOOL_TABLE_FILE}: {e}")),
    };
    let text = std::str::from_utf8(&text).map_err(|_| {
        format!("{TOOL_TABLE_FILE}: not UTF-8 text (save it again in the tool table editor)")
    })?;
    parse_tool_table(text).map_err(|e| {
        format!(
            "{TOOL_TABLE_FILE} line {} column {}: {} (fix it in the tool table editor)",
            e.line, e.col, e.message
        )
    })
}

/// The saved tool table (`GET /api/tools`), empty when none was saved.
pub(crate) async fn tools_text(State(st): State<Arc<AppState>>) -> Response {
    let path = match path_in(&st.config.job_dir, TOOL_TABLE_FILE) {
        Ok(p) => p,
        Err(e) => return refused(StatusCode::BAD_REQUEST, "", e),
    };
    tokio::fs::read_to_string(&path)
        .await
        .unwrap_or_default()
        .into_response()
}

/// Checks a tool table with the interpreter's parser and, when good, saves it into the job
/// folder (`PUT /api/tools`); errors name line and column.
pub(crate) async fn save_tools(State(st): State<Arc<AppState>>, body: Bytes) -> Response {
    let Ok(text) = std::str::from_utf8(&body) else {
        return refused(
            StatusCode::BAD_REQUEST,
            "",
            "the tool table is not UTF-8 text".into(),
        );
    };
    match check_tool_table(text) {
        Ok(rows) => {
            let path = match path_in(&st.config.job_dir, TOOL_TABLE_FILE) {
                Ok(p) => p,
                Err(e) => return refused(StatusCode::BAD_REQUEST, "", e),
            };
            if let Err(e) = tokio::fs::write(&path, text).await {
                return refused(
                    StatusCode::BAD_REQUEST,
                    "",
                    format!("{TOOL_TABLE_FILE}: {e}"),
                );
            }
            st.say(&format!("saved the tool table ({} tools)", rows.len()));
            Json(json!({"ok": true, "tools": rows})).into_response()
        }
        Err(e) => (
            StatusCode::BAD_REQUEST,
            Json(json!({"ok": false, "line": e.line, "col": e.col, "error": e.message})),
        )
            .into_response(),
    }
}
