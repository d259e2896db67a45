//! `POST /api/simulate`: the page's program replayed on a box of stock (`oficina simulate`),
//! answered with the report and the shaded stock as a PNG data URL.

use crate::api::{current_profile, ProgramQuery};
use crate::AppState;
use axum::body::Bytes;
use axum::extract::{Query, State};
use axum::http::StatusCode;
use axum::response::{IntoResponse, Response};
use axum::Json;
use base64::Engine;
use oficina_app::simulate::{simulate, SimulateRequest, StockSize, ToolChoice};
use serde::Deserialize;
use serde_json::json;
use std::sync::Arc;

/// The page's memory budget for one simulation, MB: several pages may ask at once.
const PAGE_MEMORY_MB: u64 = 128;

#[derive(Deserialize)]
pub(crate) struct SimQuery {
    /// `WxHxT` mm or `auto` (default).
    stock: Option<String>,
    /// Shape of every tool the page's tool table does not give, e.g. `flat:3`.
    tool: Option<String>,
    /// Grid cell, mm.
    resolution: Option<f64>,
}

fn bad(msg: impl Into<String>) -> (StatusCode, String) {
    (StatusCode::BAD_REQUEST, msg.into())
}

fn stock(text: Option<&str>) -> Result<StockSize, (StatusCode, String)> {
    let text = text.unwrap_or("auto").trim();
    if text.eq_ignore_ascii_case("auto") {
        return Ok(StockSize::Auto { margin: 2.0 });
    }
    let v: Vec<f64> = text
        .split(['x', 'X'])
        .map(|p| p.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| bad(format!("stock {text:?}: expected WxHxT in mm or auto")))?;
    match v[..] {
        [w, h, t] => Ok(StockSize::Given([w, h, t])),
        _ => Err(bad(format!("stock {text:?}: expected WxHxT in mm or auto"))),
    }
}

pub(crate) async fn simulate_stock(
    State(st): State<Arc<AppState>>,
    Query(q): Query<ProgramQuery>,
    Query(s): Query<SimQuery>,
    body: Bytes,
) -> Result<Response, (StatusCode, String)> {
    let text = q.text(&st, body)?;
    let dialect = q.dialect(&st)?;
    let mut run = oficina_gcode::RunOptions::check(dialect);
    // The page's saved tool table: its diameters (and shapes named in its comments).
    run.tool_table = crate::profiles::saved_tools(&st).map_err(bad)?;
    let default = match &s.tool {
        Some(t) => Some(t.parse().map_err(|e| bad(format!("{e}")))?),
        None => None,
    };
    let req = SimulateRequest {
        text,
        run,
        profile: current_profile(&st)?,
        tools: ToolChoice {
            default,
            ..ToolChoice::default()
        },
        stock: stock(s.stock.as_deref())?,
        stock_origin: None,
        resolution: s.resolution,
        memory_mb: PAGE_MEMORY_MB,
        design: None,
    };
    let (report, png) = tokio::task::spawn_blocking(move || {
        let sim = simulate(&req).map_err(|e| e.to_string())?;
        let png = oficina_sim::png_bytes(&sim.stock)?;
        Ok::<_, String>((sim.report, png))
    })
    .await
    .map_err(|e| bad(e.to_string()))?
    .map_err(bad)?;
    let url = format!(
        "data:image/png;base64,{}",
        base64::engine::general_purpose::STANDARD.encode(png)
    );
    Ok(Json(json!({"report": report, "png": url})).into_response())
}
