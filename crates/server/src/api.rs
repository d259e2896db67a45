//! The HTTP API: samples, the job folder, check summaries, preview segments, relief jobs,
//! and the page itself.

use crate::files::path_in;
use crate::jobs;
use crate::samples;
use crate::state::lock;
use crate::{auth, AppState};
use axum::body::{Body, Bytes};
use axum::extract::{DefaultBodyLimit, Path, Query, State};
use axum::http::{header, StatusCode};
use axum::response::{Html, IntoResponse, Response};
use axum::routing::{get, post};
use axum::{Json, Router};
use oficina_app::{check_program_with_tools, for_each_segment, profile, CheckOptions};
use oficina_gcode::Dialect;
use serde::Deserialize;
use serde_json::json;
use std::sync::Arc;

type ApiResult = Result<Response, (StatusCode, String)>;

fn bad(msg: impl Into<String>) -> (StatusCode, String) {
    (StatusCode::BAD_REQUEST, msg.into())
}

pub(crate) fn routes(state: Arc<AppState>) -> Router {
    let limit = state.config.upload_limit;
    Router::new()
        .route("/api/info", get(info))
        .route("/api/open", get(open_program))
        .route("/api/job", get(running_job))
        .route("/api/samples/{name}", get(sample))
        .route("/api/files", get(list_files))
        .route("/api/files/{name}", get(read_file).put(write_file))
        .route("/api/check", post(check))
        .route("/api/preview", post(preview))
        .route("/api/simulate", post(crate::simulate::simulate_stock))
        .route("/api/carve", post(jobs::carve))
        .route("/api/mill", post(jobs::mill_job))
        .route("/api/mill-job", post(crate::camjob::build))
        .route("/api/mill-job/shapes", post(crate::camjob::shapes))
        .route("/api/mill-job/stock", post(crate::camjob::stock))
        .route("/api/model", post(crate::carve_model::carve))
        .route("/api/model/mesh", post(crate::carve_model::mesh))
        .route("/api/design/offset", post(crate::design::offset))
        .route("/api/design/export", post(crate::design::export))
        .route("/api/design/fit", post(crate::design::fit))
        .route("/api/design/grade", post(crate::design::grade))
        .route("/api/design/import", post(crate::design::import))
        .route("/api/sole", post(jobs::sole_job))
        .route("/api/plot", post(jobs::plot_job))
        .route("/api/embroider", post(crate::embroider::embroider_job))
        .route("/api/stitches", post(crate::embroider::stitch_file))
        .route("/api/stitches/open", post(crate::stitches::open))
        .route("/api/stitches/alter", post(crate::stitches::alter_plan))
        .route("/api/stitches/link", post(crate::stitches::link_plans))
        .route("/api/stitches/speed", post(crate::stitches::speed))
        .route("/api/stitches/save", post(crate::stitches::save))
        .route("/api/cancel", post(jobs::cancel))
        .route("/api/profiles/check", post(crate::profiles::check))
        .route("/api/profiles/use", post(crate::profiles::use_profile))
        .route("/api/profiles/{name}", get(crate::profiles::text))
        .route(
            "/api/tools",
            get(crate::profiles::tools_text).put(crate::profiles::save_tools),
        )
        .route(
            "/api/macros",
            get(crate::macros::list).put(crate::macros::save),
        )
        .layer(DefaultBodyLimit::max(limit))
        .route_layer(axum::middleware::from_fn_with_state(
            state.clone(),
            auth::require_token,
        ))
        .with_state(state)
}

async fn info(State(st): State<Arc<AppState>>) -> Json<serde_json::Value> {
    let profiles: Vec<&str> = profile::BUNDLED.iter().map(|(n, _)| *n).collect();
    let programs: Vec<&str> = samples::PROGRAMS.iter().map(|(n, _)| *n).collect();
    let images: Vec<&str> = samples::IMAGES.iter().map(|(n, _)| *n).collect();
    let designs: Vec<&str> = samples::DESIGNS.iter().map(|(n, _)| *n).collect();
    Json(json!({
        "machine": st.config.machine,
        "profiles": profiles,
        "samples": programs,
        "images": images,
        "designs": designs,
        "upload_limit": st.config.upload_limit,
    }))
}

/// The program the page opens with: the one named at start, else the default sample.
async fn open_program(State(st): State<Arc<AppState>>) -> ApiResult {
    let name = st.config.open.as_deref().unwrap_or(samples::DEFAULT);
    let text = program_text(&st, name)?;
    // Already in the job folder: the page checks it there by name instead of uploading it.
    let saved = path_in(&st.config.job_dir, name).is_ok_and(|p| p.is_file());
    Ok(Json(json!({"name": name, "text": text.as_str(), "saved": saved})).into_response())
}

/// A file of the job folder, or else a bundled sample of that name.
pub(crate) fn program_text(st: &AppState, name: &str) -> Result<Arc<String>, (StatusCode, String)> {
    let path = path_in(&st.config.job_dir, name).map_err(bad)?;
    if path.is_file() {
        return std::fs::read_to_string(&path)
            .map(Arc::new)
            .map_err(|e| bad(format!("{name}: {e}")));
    }
    samples::PROGRAMS
        .iter()
        .find(|(n, _)| *n == name)
        .map(|(_, t)| Arc::new(t.to_string()))
        .ok_or((StatusCode::NOT_FOUND, format!("no program named {name}")))
}

async fn running_job(State(st): State<Arc<AppState>>) -> ApiResult {
    match lock(&st.job).clone() {
        Some(j) => Ok(Json(json!({"name": j.name, "text": j.text.as_str()})).into_response()),
        None => Err((StatusCode::NOT_FOUND, "no job has run".into())),
    }
}

async fn sample(Path(name): Path<String>) -> ApiResult {
    if let Some((_, t)) = samples::PROGRAMS.iter().find(|(n, _)| *n == name) {
        return Ok(t.to_string().into_response());
    }
    if let Some((_, t)) = samples::DESIGNS.iter().find(|(n, _)| *n == name) {
        return Ok(t.to_string().into_response());
    }
    if let Some((_, b)) = samples::IMAGES.iter().find(|(n, _)| *n == name) {
        return Ok(([(header::CONTENT_TYPE, "image/png")], *b).into_response());
    }
    Err((StatusCode::NOT_FOUND, format!("no sample named {name}")))
}

async fn list_files(State(st): State<Arc<AppState>>) -> ApiResult {
    let mut names = Vec::new();
    let dir = std::fs::read_dir(&st.config.job_dir).map_err(|e| bad(e.to_string()))?;
    for e in dir.flatten() {
        if e.path().is_file() {
            names.push(e.file_name().to_string_lossy().into_owned());
        }
    }
    names.sort();
    Ok(Json(names).into_response())
}

async fn read_file(State(st): State<Arc<AppState>>, Path(name): Path<String>) -> ApiResult {
    let path = path_in(&st.config.job_dir, &name).map_err(bad)?;
    match tokio::fs::read(&path).await {
        Ok(b) => Ok(b.into_response()),
        Err(_) => Err((StatusCode::NOT_FOUND, format!("no file named {name}"))),
    }
}

async fn write_file(
    State(st): State<Arc<AppState>>,
    Path(name): Path<String>,
    body: Bytes,
) -> ApiResult {
    let path = path_in(&st.config.job_dir, &name).map_err(bad)?;
    tokio::fs::write(&path, &body)
        .await
        .map_err(|e| bad(format!("{name}: {e}")))?;
    st.say(&format!("saved {name} ({} bytes)", body.len()));
    Ok(Json(json!({"name": name, "bytes": body.len()})).into_response())
}

#[derive(Deserialize)]
pub(crate) struct ProgramQuery {
    dialect: Option<String>,
    /// A file of the job folder (or a sample) instead of the body.
    file: Option<String>,
}

impl ProgramQuery {
    /// The dialect asked, else the one of the machine the program will run on: Marlin's on a
    /// Marlin board (M280 pen lifts, G4 P in ms), grbl's for other firmware (where a program
    /// without M2 is normal), LinuxCNC's for the virtual one.
    pub(crate) fn dialect(&self, st: &AppState) -> Result<Dialect, (StatusCode, String)> {
        match &self.dialect {
            None => {
                let (firmware, marlin) = st
                    .with_session(|s| {
                        Ok((
                            s.profile().is_none(),
                            oficina_app::is_marlin(&s.snapshot().uri),
                        ))
                    })
                    .map_err(bad)?;
                Ok(match (firmware, marlin) {
                    (_, true) => Dialect::Marlin,
                    (true, false) => Dialect::Grbl,
                    (false, false) => Dialect::LinuxCnc,
                })
            }
            Some(d) => d.parse().map_err(|e| bad(format!("dialect {d:?}: {e}"))),
        }
    }

    pub(crate) fn text(
        &self,
        st: &AppState,
        body: Bytes,
    ) -> Result<Arc<String>, (StatusCode, String)> {
        if let Some(name) = &self.file {
            return program_text(st, name);
        }
        String::from_utf8(body.to_vec()).map(Arc::new).map_err(|e| {
            bad(format!(
                "the program is not UTF-8 text (byte {})",
                e.utf8_error().valid_up_to()
            ))
        })
    }
}

/// The machine profile the check and the preview use: the connected virtual machine's, or
/// the default profile when the machine is real firmware.
pub(crate) fn current_profile(
    st: &AppState,
) -> Result<oficina_app::profile::Profile, (StatusCode, String)> {
    let p = st.with_session(|s| Ok(s.profile().cloned())).map_err(bad)?;
    match p {
        Some(p) => Ok(p),
        None => profile::resolve(profile::DEFAULT).map_err(|e| bad(e.to_string())),
    }
}

async fn check(
    State(st): State<Arc<AppState>>,
    Query(q): Query<ProgramQuery>,
    body: Bytes,
) -> ApiResult {
    let text = q.text(&st, body)?;
    let dialect = q.dialect(&st)?;
    let opts = CheckOptions {
        profile: current_profile(&st)?,
        dialect,
    };
    // The page's saved tool table: G43 H and G41 D as the virtual machine will run them.
    let tools = crate::profiles::saved_tools(&st).map_err(bad)?;
    // On firmware the check reads what the sender streams (M6 under its tool-change policy).
    let sender = match dialect {
        Dialect::Grbl => st
            .with_session(|s| Ok(s.tool_change_policy()))
            .map_err(bad)?,
        _ => None,
    };
    let report = tokio::task::spawn_blocking(move || match sender {
        Some(tc) => oficina_app::check_for_sender(&text, &opts, &tools, &tc),
        None => check_program_with_tools(&text, &opts, &tools),
    })
    .await
    .map_err(|e| bad(e.to_string()))?;
    // Which reading the page shows: it names it beside the counts.
    let mut report = serde_json::to_value(report).map_err(|e| bad(e.to_string()))?;
    report["dialect"] = json!(dialect.to_string());
    Ok(Json(report).into_response())
}

/// Bytes per preview segment: from and to as 6 × f32, then line << 2 | kind as u32, all
/// little-endian (the page reads them straight into typed arrays).
pub(crate) const SEGMENT_BYTES: usize = 28;
/// Segments per chunk sent: the page draws as they arrive.
const CHUNK_SEGMENTS: usize = 8192;

async fn preview(
    State(st): State<Arc<AppState>>,
    Query(q): Query<ProgramQuery>,
    body: Bytes,
) -> ApiResult {
    let text = q.text(&st, body)?;
    let profile = current_profile(&st)?;
    let dialect = q.dialect(&st)?;
    let (tx, rx) = tokio::sync::mpsc::channel::<Vec<u8>>(8);
    tokio::task::spawn_blocking(move || {
        let mut buf = Vec::with_capacity(CHUNK_SEGMENTS * SEGMENT_BYTES);
        let mut closed = false;
        for_each_segment(&text, &profile, dialect, |s| {
            if closed {
                return;
            }
            for v in s.from.iter().chain(&s.to) {
                buf.extend_from_slice(&(*v as f32).to_le_bytes());
            }
            let tag = (s.line.min(u32::MAX >> 2) << 2) | s.kind as u32;
            buf.extend_from_slice(&tag.to_le_bytes());
            if buf.len() >= CHUNK_SEGMENTS * SEGMENT_BYTES {
                let full =
                    std::mem::replace(&mut buf, Vec::with_capacity(CHUNK_SEGMENTS * SEGMENT_BYTES));
                // The page went away: stop sending (the interpreter finishes on its own).
                closed = tx.blocking_send(full).is_err();
            }
        });
        if !buf.is_empty() && !closed {
            let _ = tx.blocking_send(buf);
        }
    });
    let stream = futures_util::stream::unfold(rx, |mut rx| async move {
        rx.recv()
            .await
            .map(|b| (Ok::<_, std::io::Error>(Bytes::from(b)), rx))
    });
    Ok((
        [(header::CONTENT_TYPE, "application/octet-stream")],
        Body::from_stream(stream),
    )
        .into_response())
}

/// The page: from `--web DIR` when given (development), else the one built into the binary,
/// else a page that says how to build it.
pub(crate) fn page_service(st: &AppState) -> Router {
    match &st.config.web_dir {
        Some(dir) if dir.join("index.html").is_file() => Router::new().fallback_service(
            tower_http::services::ServeDir::new(dir)
                .fallback(tower_http::services::ServeFile::new(dir.join("index.html"))),
        ),
        None if crate::page::built() => Router::new().fallback(crate::page::serve),
        _ => Router::new().fallback(|| async {
            (
                StatusCode::OK,
                Html("<!doctype html><title>Oficina</title><h1>Oficina workbench</h1><p>The page is not built: run <code>npm ci &amp;&amp; npm run build</code> in <code>web/</code> (or <code>bash scripts/workbench</code>), then reload. The API is up under <code>/api</code>.</p>"),
            )
        }),
    }
}
