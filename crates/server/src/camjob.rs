//! CAM jobs from the page (`/api/mill-job`): the page writes the job as the TOML that
//! `oficina mill --job` reads; it is saved into the job folder beside the drawing and built
//! by `oficina_app::mill_job`, the CLI's own call. `/api/mill-job/shapes` answers the
//! drawing's shapes with the ids the import report gives, for the page to draw and select.
//! `/api/mill-job/stock` answers the stock after an operation: the job stopped there
//! (`oficina_app::mill_job_upto`, judged for gouge) and its program simulated as
//! `oficina simulate` does, each tool with its shape.

use crate::files::path_in;
use crate::jobs::{bad, compute, output_name, CamError};
use crate::AppState;
use axum::extract::State;
use axum::response::{IntoResponse, Response};
use axum::Json;
use base64::Engine;
use oficina_app::simulate::{simulate, SimulateRequest, StockSize, ToolChoice};
use oficina_app::{job_shapes, mill_job, mill_job_upto, profile, JobOptions, JobResult};
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

/// The stock after an operation: the job, how far into its cutting order, the grid cell.
#[derive(Deserialize)]
pub(crate) struct StockAfter {
    #[serde(flatten)]
    job: JobText,
    /// The number of operations cut, in cutting order (1 = the first).
    upto: usize,
    /// Grid cell, mm; default: the finest the memory budget allows for the whole job's path.
    resolution: Option<f64>,
}

/// The memory budget of one stock simulation from the page, MB.
const STOCK_MEMORY_MB: u64 = 128;

/// The machine profile the page names (default: the bundled default).
fn machine(st: &AppState, name: Option<&str>) -> Result<profile::Profile, String> {
    let spec = crate::profiles::profile_spec(st, name.unwrap_or(profile::DEFAULT));
    spec.and_then(|s| profile::resolve(&s).map_err(|e| e.to_string()))
}

/// The simulation of a job's (first) program on its stock, each tool as the job gives it.
fn simulate_job(
    r: &JobResult,
    machine: &Result<profile::Profile, String>,
    resolution: Option<f64>,
) -> Result<oficina_app::simulate::Simulation, oficina_app::Error> {
    let program = r
        .programs
        .first()
        .ok_or_else(|| oficina_app::Error("the job made no program".into()))?;
    let mut tools = ToolChoice::default();
    for o in &r.ops {
        let tool = o.tool.parse().map_err(oficina_app::Error::from_display)?;
        tools.by_number.push((o.tool_number, tool));
    }
    let (stock, stock_origin) = match r.stock.size {
        Some([w, h]) => (
            StockSize::Given([w, h, r.stock.thickness]),
            Some([r.stock.corner[0], r.stock.corner[1], 0.0]),
        ),
        None => (StockSize::Auto { margin: 2.0 }, None),
    };
    let profile = match machine {
        Ok(p) => p.clone(),
        Err(_) => profile::resolve(profile::DEFAULT).map_err(oficina_app::Error::from_display)?,
    };
    simulate(&SimulateRequest {
        text: Arc::new(program.judged.program.clone()),
        run: oficina_gcode::RunOptions::check(oficina_gcode::Dialect::LinuxCnc),
        profile,
        tools,
        stock,
        stock_origin,
        resolution,
        memory_mb: STOCK_MEMORY_MB,
        design: None,
    })
}

pub(crate) async fn stock(
    State(st): State<Arc<AppState>>,
    Json(req): Json<StockAfter>,
) -> Result<Response, CamError> {
    let path = write_job(&st, &req.job).await?;
    let machine = machine(&st, req.job.profile.as_deref());
    let (upto, resolution) = (req.upto, req.resolution);
    let (r, sim, png) = compute(&st, move |fb| {
        let r = mill_job_upto(&path, &JobOptions::default(), &machine, Some(upto), fb)?;
        let sim = simulate_job(&r, &machine, resolution)?;
        let png = oficina_sim::png_bytes(&sim.stock).map_err(oficina_app::Error)?;
        Ok((r, sim, png))
    })
    .await?;
    let judged = &r.programs[0].judged;
    let last = r.ops.last().map_or(String::new(), |o| o.name.clone());
    let png = format!(
        "data:image/png;base64,{}",
        base64::engine::general_purpose::STANDARD.encode(png)
    );
    Ok(Json(json!({
        "upto": upto,
        "last": last,
        "ops": r.ops.iter().map(|o| o.index).collect::<Vec<_>>(),
        "report": sim.report,
        "judged": judged.summary_lines(),
        "gouged": judged.gouged(),
        "png": png,
    }))
    .into_response())
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
    let machine = machine(&st, req.profile.as_deref());
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
        "stock": r.stock,
    }))
    .into_response())
}
