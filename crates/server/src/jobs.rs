//! The job endpoints: milling, sole molds, plots and reliefs from a file of the job folder
//! (uploaded there first), with progress on the live channel and one cancel button. Each
//! calls its `oficina_app` pipeline, the one the CLI calls, and writes the programs it makes
//! into the job folder.

use crate::files::{path_in, safe_name};
use crate::state::lock;
use crate::AppState;
use axum::body::Bytes;
use axum::extract::{Query, State};
use axum::http::StatusCode;
use axum::response::{IntoResponse, Response};
use axum::Json;
use oficina_app::{carve_relief, profile, Error, Feedback, ReliefParams};
use oficina_app::{mill, MillParams};
use oficina_app::{plot, PlotFormat, PlotParams};
use oficina_app::{sole, SoleParams};
use serde::Deserialize;
use serde_json::{json, Value};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};

/// A CAM job's failure as the page shows it: the message, and the form field it is about.
pub(crate) struct CamError(StatusCode, Error);

impl IntoResponse for CamError {
    fn into_response(self) -> Response {
        let body = json!({
            "error": self.1.0,
            "field": self.1.field(),
            "cancelled": self.1.is_cancelled(),
        });
        (self.0, Json(body)).into_response()
    }
}

pub(crate) fn bad(msg: impl Into<String>) -> CamError {
    CamError(StatusCode::BAD_REQUEST, Error(msg.into()))
}

impl From<Error> for CamError {
    fn from(e: Error) -> CamError {
        let code = if e.is_cancelled() {
            StatusCode::CONFLICT
        } else {
            StatusCode::BAD_REQUEST
        };
        CamError(code, e)
    }
}

/// The job being computed, so `/api/cancel` can stop it: one at a time.
#[derive(Default)]
pub struct Computing(Mutex<Option<Arc<AtomicBool>>>);

/// Runs `work` on a blocking thread with progress on the live channel. A cancel sets the
/// job's flag, which the pipelines read inside their long loops; the answer comes once the
/// thread has stopped, so a cancelled job never computes on beside the next one.
pub(crate) async fn compute<T: Send + 'static>(
    st: &Arc<AppState>,
    work: impl FnOnce(Feedback) -> Result<T, Error> + Send + 'static,
) -> Result<T, CamError> {
    let cancel = Arc::new(AtomicBool::new(false));
    {
        let mut c = lock(&st.computing.0);
        if let Some(f) = c.as_ref() {
            let msg = if f.load(Ordering::Relaxed) {
                "the cancelled job is still stopping: try again in a moment"
            } else {
                "another job is being computed: wait for it or cancel it"
            };
            return Err(CamError(StatusCode::CONFLICT, Error(msg.into())));
        }
        *c = Some(cancel.clone());
    }
    let live = st.clone();
    let flag = cancel.clone();
    let task = tokio::task::spawn_blocking(move || {
        let last = Mutex::new((String::new(), -1i64));
        let progress = |stage: &str, f: f64| {
            // At most a hundred progress messages per stage.
            let pct = (f * 100.0) as i64;
            let mut l = lock(&last);
            if l.0 != stage || l.1 != pct {
                *l = (stage.to_string(), pct);
                let _ = live
                    .live
                    .send(json!({"type": "progress", "stage": stage, "fraction": f}).to_string());
            }
        };
        work(Feedback {
            progress: &progress,
            cancel: &flag,
        })
    });
    let result = match task.await {
        // Finished as the cancel came: its result is dropped all the same.
        Ok(Ok(_)) if cancel.load(Ordering::Relaxed) => Err(CamError::from(Error::cancelled())),
        Ok(r) => r.map_err(CamError::from),
        Err(e) => Err(bad(e.to_string())),
    };
    let mut c = lock(&st.computing.0);
    if c.as_ref().is_some_and(|f| Arc::ptr_eq(f, &cancel)) {
        *c = None;
    }
    result
}

pub(crate) async fn cancel(State(st): State<Arc<AppState>>) -> Response {
    match lock(&st.computing.0).as_ref() {
        Some(f) => {
            f.store(true, Ordering::Relaxed);
            st.say("cancelled the job being computed");
            Json(json!({"cancelled": true})).into_response()
        }
        None => Json(json!({"cancelled": false})).into_response(),
    }
}

/// A CAM job on a file of the job folder (not `oficina_app::JobRequest`, which starts a
/// program on the machine).
#[derive(Deserialize)]
pub(crate) struct CamRequest<P> {
    /// The input's name in the job folder.
    file: Option<String>,
    #[serde(default)]
    params: P,
    /// The machine profile (plots: the plotter); default: the bundled default.
    profile: Option<String>,
}

pub(crate) fn input(st: &AppState, file: &Option<String>) -> Result<std::path::PathBuf, CamError> {
    let name = file
        .as_deref()
        .ok_or_else(|| bad("no input file: upload one first"))?;
    let path = path_in(&st.config.job_dir, name).map_err(bad)?;
    if !path.is_file() {
        return Err(CamError(
            StatusCode::NOT_FOUND,
            Error(format!("{name}: no such file in the job folder")),
        ));
    }
    Ok(path)
}

/// `plate.svg` → `plate.pocket.ngc`.
pub(crate) fn output_name(input: &str, suffix: &str) -> Result<String, CamError> {
    let stem = input.rsplit_once('.').map_or(input, |(s, _)| s);
    let name = format!("{stem}.{suffix}");
    safe_name(&name).map_err(bad)?;
    Ok(name)
}

async fn save(st: &AppState, name: &str, text: &str) -> Result<(), CamError> {
    let path = path_in(&st.config.job_dir, name).map_err(bad)?;
    tokio::fs::write(&path, text)
        .await
        .map_err(|e| bad(format!("{name}: {e}")))
}

fn estimate_profile(
    st: &AppState,
    spec: Option<&str>,
) -> Result<oficina_app::profile::Profile, String> {
    let spec = crate::profiles::profile_spec(st, spec.unwrap_or(profile::DEFAULT))?;
    profile::resolve(&spec).map_err(|e| e.to_string())
}

pub(crate) async fn mill_job(
    State(st): State<Arc<AppState>>,
    Json(req): Json<CamRequest<MillParams>>,
) -> Result<Response, CamError> {
    let path = input(&st, &req.file)?;
    let profile = estimate_profile(&st, req.profile.as_deref());
    let params = req.params;
    let r = compute(&st, move |fb| mill(&path, &params, &profile, fb)).await?;
    let file = req.file.as_deref().unwrap_or_default();
    let name = output_name(file, &format!("{}.ngc", r.op_name.replace(' ', "-")))?;
    save(&st, &name, &r.judged.program).await?;
    st.say(&format!(
        "milled {file} ({}, {} moves) into {name}",
        r.op_name, r.moves
    ));
    Ok(Json(json!({
        "name": name,
        "text": r.judged.program,
        "report": r.judged.summary_lines(),
        "judged": r.judged,
        "warning": r.warning,
        "imported": r.imported,
        "preview_svg": r.preview_svg,
    }))
    .into_response())
}

pub(crate) async fn sole_job(
    State(st): State<Arc<AppState>>,
    Json(req): Json<CamRequest<SoleParams>>,
) -> Result<Response, CamError> {
    let path = input(&st, &req.file)?;
    let profile = estimate_profile(&st, req.profile.as_deref());
    let params = req.params;
    let ext = params.post.extension();
    let r = compute(&st, move |fb| sole(&path, &params, &profile, fb)).await?;
    let file = req.file.as_deref().unwrap_or_default();
    let mut programs: Vec<Value> = Vec::new();
    for p in &r.programs {
        let name = output_name(file, &format!("{}.{ext}", p.name))?;
        save(&st, &name, &p.judged.program).await?;
        programs.push(json!({
            "name": name,
            "report": p.judged.summary_lines(),
            "moves": p.moves,
        }));
    }
    st.say(&format!(
        "sole molds from {file}: {} programs",
        programs.len()
    ));
    let first = r
        .programs
        .first()
        .ok_or_else(|| bad("the job made no program"))?;
    Ok(Json(json!({
        "name": programs[0]["name"],
        "text": first.judged.program,
        "summary": r.summary,
        "programs": programs,
    }))
    .into_response())
}

pub(crate) async fn plot_job(
    State(st): State<Arc<AppState>>,
    Json(req): Json<CamRequest<PlotParams>>,
) -> Result<Response, CamError> {
    let path = match &req.file {
        Some(_) => Some(input(&st, &req.file)?),
        None => None,
    };
    let spec = req.profile.as_deref().unwrap_or("pen-plotter");
    let resolved = crate::profiles::profile_spec(&st, spec).map_err(bad)?;
    let machine = profile::resolve(&resolved).map_err(|e| bad(format!("profile {spec}: {e}")))?;
    let params = req.params;
    let ext = match params.format {
        PlotFormat::Hpgl => "plt",
        _ => "ngc",
    };
    let r = compute(&st, move |fb| plot(path.as_deref(), &params, &machine, fb)).await?;
    let name = output_name(
        req.file.as_deref().unwrap_or("text"),
        &format!("plot.{ext}"),
    )?;
    save(&st, &name, &r.prepared.program).await?;
    let b = r.prepared.bounds;
    st.say(&format!("plotted into {name} for {spec}"));
    let pens: Vec<Value> = r
        .prepared
        .plot
        .pens
        .iter()
        .map(|p| json!({"name": p.name, "strokes": p.strokes.len()}))
        .collect();
    let l = r.prepared.plot.lengths();
    Ok(Json(json!({
        "name": name,
        "text": r.prepared.program,
        "notes": r.notes,
        "pens": pens,
        "bounds": b,
        "seconds": r.seconds,
        // What is drawn (after fills, occult, crop and passes), mm.
        "lengths": {"pen_down": l.pen_down, "pen_up": l.pen_up, "strokes": l.strokes},
        "preview_svg": r.prepared.preview,
        // The virtual machine to run it on: the plotter it was made for.
        "machine": format!("virtual:{resolved}"),
    }))
    .into_response())
}

/// The image's name (for messages and the program's name), beside the relief parameters in
/// the same query (serde's `flatten` would read every number as a string).
#[derive(Deserialize)]
pub(crate) struct ImageName {
    name: String,
}

pub(crate) async fn carve(
    State(st): State<Arc<AppState>>,
    Query(q): Query<ImageName>,
    Query(params): Query<ReliefParams>,
    body: Bytes,
) -> Result<Response, CamError> {
    let stem = q.name.rsplit_once('.').map_or(q.name.as_str(), |(s, _)| s);
    let out_name = format!("{}.nc", safe_name(stem).map_err(bad)?);
    let name = q.name.clone();
    let result = compute(&st, move |fb| carve_relief(&name, &body, &params, fb)).await?;
    save(&st, &out_name, &result.program).await?;
    st.say(&format!(
        "carved {} ({} x {} pixels of {:.3} mm) into {out_name}",
        q.name, result.pixels[0], result.pixels[1], result.pixel_size
    ));
    Ok(Json(json!({"name": out_name, "text": result.program})).into_response())
}
