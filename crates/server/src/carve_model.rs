//! 3D models (STL, OBJ) in the workbench. `POST /api/model/mesh` answers a model of the job
//! folder placed as `oficina carve MODEL` places it: its box and its triangles, for the page
//! to draw. `POST /api/model` carves it with the CLI's own calls (`MeshSource::load`,
//! `evaluate_mesh`, the same header and post) and answers the program, saved beside the
//! model, with its simulated stock, gouge, leftover and times. Both take `{file, params}`
//! as the page's other processes do.

use crate::files::path_in;
use crate::jobs::{bad, compute, output_name, CamError};
use crate::AppState;
use axum::extract::State;
use axum::response::{IntoResponse, Response};
use axum::Json;
use base64::Engine;
use oficina_app::carve::relief_post;
use oficina_app::carve_mesh::{evaluate_mesh, model_header, MeshFinish, MeshOptions, MeshSource};
use oficina_app::{profile, Error};
use oficina_sim::carve::Settings;
use serde::Deserialize;
use serde_json::json;
use std::sync::Arc;

/// Memory budget of one carving from the page, MB (`oficina carve`'s default).
const MEMORY_MB: u64 = 2048;

/// A model of the job folder and the form's values.
#[derive(Deserialize)]
pub(crate) struct ModelRequest<P> {
    /// The model's name in the job folder.
    file: String,
    params: P,
}

/// The model's placement (`oficina carve`'s --scale, --rotate, --size).
#[derive(Deserialize)]
pub(crate) struct Placement {
    scale: f64,
    rotate: f64,
    size: Option<f64>,
}

/// The carve form: `oficina carve`'s flags by their names (the page gives every one).
#[derive(Deserialize)]
pub(crate) struct CarveForm {
    tool: String,
    rough_tool: Option<String>,
    scallop: f64,
    stepover: Option<f64>,
    rough_stepover: f64,
    stepdown: f64,
    allowance: f64,
    direction: String,
    one_way: bool,
    no_rest: bool,
    feed: f64,
    plunge_feed: f64,
    rpm: f64,
    safe_z: f64,
    post: String,
    allow_m6: bool,
    stock_top: Option<f64>,
    stock_bottom: Option<f64>,
    angle: Option<f64>,
    tolerance: f64,
    pixel_size: Option<f64>,
    /// Finishing: raster, waterline or mix (`--strategy`); absent: the CLI's default.
    #[serde(default = "default_strategy")]
    strategy: String,
    /// Mix's slope limit, degrees (`--steep`).
    #[serde(default = "default_steep")]
    steep: f64,
    /// Roughing: zlevel or heightfield (`--roughing`).
    #[serde(default = "default_roughing")]
    roughing: String,
    /// Machine profile that times the program (default: `oficina carve`'s).
    profile: Option<String>,
}

// The defaults of `oficina carve --strategy --steep --roughing`, for forms written before them.
fn default_strategy() -> String {
    "raster".into()
}
fn default_steep() -> f64 {
    45.0
}
fn default_roughing() -> String {
    "zlevel".into()
}

/// The carve form with the placement.
#[derive(Deserialize)]
pub(crate) struct CarveParams {
    #[serde(flatten)]
    place: Placement,
    #[serde(flatten)]
    form: CarveForm,
}

fn source(st: &AppState, file: &str, p: &Placement) -> Result<MeshSource, CamError> {
    Ok(MeshSource {
        path: path_in(&st.config.job_dir, file).map_err(bad)?,
        scale: p.scale,
        rotate: p.rotate,
        size: p.size,
    })
}

fn budget() -> u64 {
    MEMORY_MB.saturating_mul(1 << 20)
}

/// The placed model: its box, triangle count and corners as little-endian f32 (base64),
/// and the work offset the 3D view draws programs at (the model goes where its program is).
pub(crate) async fn mesh(
    State(st): State<Arc<AppState>>,
    Json(req): Json<ModelRequest<Placement>>,
) -> Result<Response, CamError> {
    let source = source(&st, &req.file, &req.params)?;
    let offset = crate::api::current_profile(&st)
        .map(|p| p.work_offset)
        .map_err(|(_, e)| bad(e))?;
    // Not one of the computed jobs: drawing a model while a carving runs is no conflict.
    let mesh = tokio::task::spawn_blocking(move || source.load(budget()))
        .await
        .map_err(|e| bad(e.to_string()))??;
    let mut bytes = Vec::with_capacity(mesh.triangles.len() * 36);
    for v in mesh.triangles.iter().flatten().flatten() {
        bytes.extend_from_slice(&(*v as f32).to_le_bytes());
    }
    Ok(Json(json!({
        "file": req.file,
        "triangles": mesh.triangles.len(),
        "bounds": mesh.bounds(),
        "work_offset": offset,
        "positions": base64::engine::general_purpose::STANDARD.encode(bytes),
    }))
    .into_response())
}

fn settings(f: &CarveForm) -> Result<Settings, Error> {
    Ok(Settings {
        tool: f.tool.clone(),
        rough_tool: f.rough_tool.clone().filter(|t| !t.trim().is_empty()),
        scallop: f.scallop,
        stepover: f.stepover,
        rough_stepover: f.rough_stepover,
        stepdown: f.stepdown,
        allowance: f.allowance,
        direction: f.direction.parse().map_err(Error)?,
        one_way: f.one_way,
        no_rest: f.no_rest,
        feed: f.feed,
        plunge_feed: f.plunge_feed,
        rpm: f.rpm,
        safe_z: f.safe_z,
    })
}

pub(crate) async fn carve(
    State(st): State<Arc<AppState>>,
    Json(req): Json<ModelRequest<CarveParams>>,
) -> Result<Response, CamError> {
    let source = source(&st, &req.file, &req.params.place)?;
    let name = output_name(&req.file, "nc")?;
    let profile_name = req
        .params
        .form
        .profile
        .clone()
        .unwrap_or_else(|| profile::DEFAULT.to_string());
    let machine = crate::profiles::profile_spec(&st, &profile_name)
        .and_then(|s| profile::resolve(&s).map_err(|e| e.to_string()))
        .map_err(bad)?;
    let file = req.file.clone();
    let form = req.params.form;
    let e = compute(&st, move |fb| {
        let mesh = source.load(budget())?;
        let settings = settings(&form)?;
        let opts = MeshOptions {
            angle: form.angle,
            pixel: form.pixel_size,
            stock_top: form.stock_top,
            stock_bottom: form.stock_bottom,
            tolerance: form.tolerance,
            roughing: form
                .roughing
                .parse()
                .map_err(|e: String| Error(format!("--roughing: {e}")))?,
        };
        let finish = MeshFinish {
            strategy: form
                .strategy
                .parse()
                .map_err(|e: String| Error(format!("--strategy: {e}")))?,
            limit: form.steep,
        };
        let mut header = vec![(
            "command".to_string(),
            "the workbench's model carving (oficina carve MODEL)".to_string(),
        )];
        header.extend(model_header(&file, &mesh, &settings, &profile_name));
        let post = relief_post(&form.post, form.allow_m6, header)?;
        evaluate_mesh(
            &mesh,
            &settings,
            &opts,
            &finish,
            &machine,
            &post,
            budget(),
            fb.progress,
            fb.cancel,
        )
    })
    .await?;
    let out = path_in(&st.config.job_dir, &name).map_err(bad)?;
    tokio::fs::write(&out, &e.program)
        .await
        .map_err(|err| bad(format!("{name}: {err}")))?;
    let png = oficina_sim::png_bytes(&e.stock).map_err(bad)?;
    let ops: Vec<_> = e
        .toolpath
        .operations
        .iter()
        .map(|o| json!({"name": o.name, "tool_number": o.tool_number, "tool": o.tool.spec(), "moves": o.moves.len()}))
        .collect();
    st.say(&format!(
        "carved the model {} into {name}: {} moves",
        req.file,
        e.toolpath.move_count()
    ));
    let r = &e.report;
    Ok(Json(json!({
        "name": name,
        "text": e.program,
        "triangles": e.triangles,
        "ops": ops,
        "report": {
            "max_gouge": r.max_gouge,
            "leftover_max": r.leftover_max,
            "leftover_mean": r.leftover_mean,
            "scallop_max": r.scallop_max,
            "scallop_mean": r.scallop_mean,
        },
        "grid": [e.stock.width, e.stock.height, e.stock.pixel],
        "planner_s": e.planner.as_ref().ok(),
        "planner_error": e.planner.as_ref().err(),
        "feed_only_s": e.feed_only_s,
        "png": format!(
            "data:image/png;base64,{}",
            base64::engine::general_purpose::STANDARD.encode(png)
        ),
    }))
    .into_response())
}
