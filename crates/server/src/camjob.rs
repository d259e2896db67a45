//! CAM jobs from the page (`/api/mill-job`): the page writes the job as the TOML that
//! `oficina mill --job` reads; it is saved into the job folder beside the drawing and built
//! by `oficina_app::mill_job`, the CLI's own call. `/api/mill-job/shapes` answers the
//! drawing's shapes with the ids the import report gives, for the page to draw and select.

use crate::files::path_in;
use crate::jobs::{bad, compute, output_name, CamError};
use crate::AppState;
use axum::extract::State;
use axum::response::{IntoResponse, Response};
use axum::Json;
use oficina_app::{job_shapes, mill_job, profile, JobOptions};
use serde::Deserialize;
use serde_json::json;
use std::sync::Arc;

/// A job as the page sends it: its file name in the job folder and its TOML text.
#[derive(Deserialize)]
pub(crate) struct JobText {
    /// `mount.job.toml`: 1–100 plain characters ending in `.toml`.
    name: String,
    /// The job, as `oficina mill --job` reads it.
    toml: String,
    /// The machine profile that times the program; default: the bundled default.
    profile: Option<String>,
}

/// Writes the job into the job folder (the drawing it names is read from there).
async fn write_job(st: &AppState, req: &JobText) -> Result<std::path::PathBuf, CamError> {
    if !req.name.ends_with(".toml") {
        return Err(bad(format!("{}: a job's name ends in .toml", req.name)));
    }
    let path = path_in(&st.config.job_dir, &req.name).map_err(bad)?;
    tokio::fs::write(&path, &req.toml)
        .await
        .map_err(|e| bad(format!("{}: {e}", req.name)))?;
    Ok(path)
}

pub(crate) async fn shapes(
    State(st): State<Arc<AppState>>,
    Json(req): Json<JobText>,
) -> Result<Response, CamError> {
    let path = write_job(&st, &req).await?;
    let (shapes, warnings) = compute(&st, move |_| job_shapes(&path)).await?;
    Ok(Json(json!({"shapes": shapes, "warnings": warnings})).into_response())
}

pub(crate) async fn build(
    State(st): State<Arc<AppState>>,
    Json(req): Json<JobText>,
) -> Result<Response, CamError> {
    let path = write_job(&st, &req).await?;
    let spec =
        crate::profiles::profile_spec(&st, req.profile.as_deref().unwrap_or(profile::DEFAULT));
    let machine = spec.and_then(|s| profile::resolve(&s).map_err(|e| e.to_string()));
    let opts = JobOptions::default();
    let r = compute(&st, move |fb| mill_job(&path, &opts, &machine, fb)).await?;
    let stem = req.name.trim_end_matches(".toml").trim_end_matches(".job");
    let name = output_name(&format!("{stem}.x"), "ngc")?;
    let program = r
        .programs
        .first()
        .ok_or_else(|| bad("the job made no program"))?;
    let judged = &program.judged;
    let text = judged.program.clone();
    let out = path_in(&st.config.job_dir, &name).map_err(bad)?;
    tokio::fs::write(&out, &text)
        .await
        .map_err(|e| bad(format!("{name}: {e}")))?;
    let ops: Vec<_> = r
        .ops
        .iter()
        .map(|o| {
            json!({
                "index": o.index,
                "name": o.name,
                "tool_number": o.tool_number,
                "tool": o.tool,
                "shapes": o.shapes,
                "moves": o.moves,
                "depth": o.depth,
                "feed": o.feeds.feed,
                "plunge_feed": o.feeds.plunge_feed,
                "rpm": o.feeds.rpm,
                "feed_source": o.feeds.source,
                "path": o.path,
            })
        })
        .collect();
    st.say(&format!(
        "milled the job {} into {name}: {} operations, {} tool loads",
        req.name,
        ops.len(),
        r.tool_loads
    ));
    Ok(Json(json!({
        "name": name,
        "text": text,
        "report": judged.summary_lines(),
        "judged": judged,
        "gouged": judged.gouged(),
        "ops": ops,
        "tool_loads": r.tool_loads,
        "warnings": r.warnings,
        "imported": r.imported,
        "shapes": r.shapes,
        "preview_svg": r.preview_svg,
        // The stock after each operation is not simulated apart: only the whole program's.
        "stock_per_op": false,
    }))
    .into_response())
}
