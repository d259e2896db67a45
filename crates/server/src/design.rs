//! The design editor's calls (`/api/design/*`): the page sends its whole design (the
//! `*.oficina.json` schema) with what to do; the geometry is `oficina_app::design`'s, the
//! same the `oficina design` command runs.

use crate::jobs::{bad, CamError};
use axum::response::{IntoResponse, Response};
use axum::Json;
use oficina_app::design::{export as export_design, offset as offset_design, parse_design, Design};
use serde::Deserialize;
use serde_json::json;

/// The design as the page holds it, checked as a file would be.
fn design_of(v: &serde_json::Value) -> Result<Design, CamError> {
    parse_design(&v.to_string(), "the design").map_err(|e| bad(e.to_string()))
}

#[derive(Deserialize)]
pub(crate) struct OffsetRequest {
    design: serde_json::Value,
    ids: Vec<u64>,
    distance: f64,
}

/// `{design, ids, distance}` → `{entities}`: the new offset contours.
pub(crate) async fn offset(Json(req): Json<OffsetRequest>) -> Result<Response, CamError> {
    let design = design_of(&req.design)?;
    let entities =
        offset_design(&design, &req.ids, req.distance).map_err(|e| bad(e.to_string()))?;
    Ok(Json(json!({ "entities": entities })).into_response())
}

#[derive(Deserialize)]
pub(crate) struct ExportRequest {
    design: serde_json::Value,
    format: String,
}

/// `{design, format: "svg" | "dxf"}` → `{text}`.
pub(crate) async fn export(Json(req): Json<ExportRequest>) -> Result<Response, CamError> {
    let design = design_of(&req.design)?;
    let text = export_design(&design, &req.format).map_err(|e| bad(e.to_string()))?;
    Ok(Json(json!({ "text": text })).into_response())
}

#[derive(Deserialize)]
pub(crate) struct FitRequest {
    points: Vec<[f64; 2]>,
    method: String,
    tol: f64,
}

/// `{points, method, tol}` → `{shape, max_deviation, blocks}`: a digitised contour fitted.
pub(crate) async fn fit(Json(req): Json<FitRequest>) -> Result<Response, CamError> {
    let f = oficina_app::design::fit(&req.points, &req.method, req.tol)
        .map_err(|e| bad(e.to_string()))?;
    Ok(
        Json(json!({ "shape": f.shape, "max_deviation": f.max_deviation, "blocks": f.blocks }))
            .into_response(),
    )
}

#[derive(Deserialize)]
pub(crate) struct GradeRequest {
    design: serde_json::Value,
    points: Vec<[f64; 2]>,
    from_size: f64,
    sizes: Vec<f64>,
    system: String,
    shrink: f64,
    tol: f64,
}

/// `{design, points, from_size, sizes, system, shrink, tol}` → `{design, sizes}`: the
/// digitised points graded to each size and mirrored as `oficina sole` does, each foot
/// added on its layer (`size 40 left`, …); `sizes` reports each size's fit.
pub(crate) async fn grade(Json(req): Json<GradeRequest>) -> Result<Response, CamError> {
    let mut design = design_of(&req.design)?;
    let params = oficina_app::design::GradeParams {
        from_size: req.from_size,
        sizes: req.sizes,
        system: req.system,
        shrink: req.shrink,
        tol: req.tol,
    };
    let graded =
        tokio::task::spawn_blocking(move || oficina_app::design::grade(&req.points, &params))
            .await
            .map_err(|e| bad(e.to_string()))?
            .map_err(|e| bad(e.to_string()))?;
    let mut report = Vec::new();
    for g in graded {
        report.push(json!({"size": g.size, "method": g.method, "blocks": g.blocks, "max_deviation": g.max_deviation}));
        oficina_app::design::add_graded(&mut design, g.size, g.feet);
    }
    Ok(Json(json!({ "design": design, "sizes": report })).into_response())
}

#[derive(Deserialize)]
pub(crate) struct ImportRequest {
    text: String,
    name: String,
}

/// `{text, name}` → `{design}`: seed 001's graphic file as a design.
pub(crate) async fn import(Json(req): Json<ImportRequest>) -> Result<Response, CamError> {
    let design = oficina_app::design::design_from_seed001(&req.text, &req.name)
        .map_err(|e| bad(e.to_string()))?;
    Ok(Json(json!({ "design": design })).into_response())
}
