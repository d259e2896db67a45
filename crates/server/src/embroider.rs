//! The embroidery endpoints: a design of the job folder sewn by `oficina_app::embroider` (the
//! pipeline `oficina embroider` runs) into a DST/EXP file there, and any stitch file of the job
//! folder read back with its production sheet and its run on the needle-synchronised table.
//! The answer carries the plan as the file holds it, in sewing order, for the page to draw in
//! thread colours; the figures are the sheet's, computed by the application layer.

use crate::files::path_in;
use crate::jobs::{bad, compute, input, output_name, CamError};
use crate::AppState;
use axum::extract::State;
use axum::response::{IntoResponse, Response};
use axum::Json;
use oficina_app::embroider::{
    embroider_text, read_stitch_file, sheet_document_with_render, sheet_of, EmbroiderParams,
};
use oficina_app::Error;
use oficina_stitch::{Align, Format, Kind, Params, Sheet, StitchPlan, Text, Trim, DEFAULT_FONT};
use serde::Deserialize;
use serde_json::{json, Value};
use std::sync::Arc;

/// The form's fields, named as `oficina embroider`'s flags (so an error naming `--hoop`
/// lands beside the hoop field); absent fields take the CLI's defaults.
#[derive(Deserialize)]
#[serde(default, deny_unknown_fields)]
pub(crate) struct EmbroiderForm {
    stitch_length: f64,
    fill_angle: f64,
    fill_spacing: f64,
    fill_stitch_length: f64,
    satin_spacing: f64,
    satin_min_width: f64,
    pull_compensation: f64,
    underlay: bool,
    ties: bool,
    fill_closed: bool,
    trim_length: f64,
    /// A hoop name or seed code; empty or absent = the smallest that fits.
    hoop: Option<String>,
    /// dst, exp, pes, pes-v1, pec, jef, vp3, xxx, u01 or ram.
    format: String,
    /// The table: embroidery-table or a motion profile.
    machine: String,
    ppm: Option<f64>,
    pieces: u32,
    /// Lettering added to the design (`|` starts a line); empty = none.
    text: String,
    /// Its bundled font.
    font: String,
    /// Its cap height, mm.
    text_size: f64,
    /// left, center or right.
    text_align: String,
    /// Where its first baseline is anchored, mm (y up), design coordinates; both absent:
    /// under the design, centred on it (or at its edge as aligned).
    text_x: Option<f64>,
    text_y: Option<f64>,
    /// never, line, word or letter: where the thread is cut between glyphs.
    text_trim: String,
}

impl Default for EmbroiderForm {
    fn default() -> EmbroiderForm {
        let p = Params::default();
        let e = EmbroiderParams::default();
        EmbroiderForm {
            stitch_length: p.stitch_length,
            fill_angle: p.fill_angle_deg,
            fill_spacing: p.fill_spacing,
            fill_stitch_length: p.fill_stitch_length,
            satin_spacing: p.satin_spacing,
            satin_min_width: p.satin_min_width,
            pull_compensation: p.pull_compensation,
            underlay: p.underlay,
            ties: p.ties,
            fill_closed: p.fill_closed,
            trim_length: p.trim_length,
            hoop: None,
            format: e.format.extension().into(),
            machine: e.table,
            ppm: None,
            pieces: e.pieces,
            text: String::new(),
            font: DEFAULT_FONT.into(),
            text_size: Text::default().size,
            text_align: "center".into(),
            text_x: None,
            text_y: None,
            text_trim: "never".into(),
        }
    }
}

impl EmbroiderForm {
    /// The lettering of the form, if it has a text.
    fn text(&self) -> Result<Option<Text>, CamError> {
        if self.text.trim().is_empty() {
            return Ok(None);
        }
        let align = Align::from_id(&self.text_align).ok_or_else(|| {
            bad(format!(
                "--text-align {}: use left, center or right",
                self.text_align
            ))
        })?;
        Ok(Some(Text {
            text: self.text.clone(),
            font: self.font.clone(),
            size: self.text_size,
            align,
            at: oficina_geom::Point::new(self.text_x.unwrap_or(0.0), self.text_y.unwrap_or(0.0)),
            under_design: self.text_x.is_none() && self.text_y.is_none(),
            trim: Trim::from_id(&self.text_trim).ok_or_else(|| {
                bad(format!(
                    "--text-trim {}: use never, line, word or letter",
                    self.text_trim
                ))
            })?,
            ..Text::default()
        }))
    }

    fn params(self) -> Result<EmbroiderParams, CamError> {
        let format = Format::from_id(&self.format).ok_or_else(|| {
            let ids: Vec<&str> = Format::EVERY.iter().map(|f| f.id()).collect();
            bad(format!("--format {}: use {}", self.format, ids.join(", ")))
        })?;
        let stitch = Params {
            stitch_length: self.stitch_length,
            fill_angle_deg: self.fill_angle,
            fill_spacing: self.fill_spacing,
            fill_stitch_length: self.fill_stitch_length,
            satin_spacing: self.satin_spacing,
            satin_min_width: self.satin_min_width,
            pull_compensation: self.pull_compensation,
            underlay: self.underlay,
            ties: self.ties,
            fill_closed: self.fill_closed,
            trim_length: self.trim_length,
            ..Params::default()
        };
        let params = EmbroiderParams {
            stitch,
            format,
            hoop: self.hoop.filter(|h| !h.trim().is_empty()),
            table: self.machine,
            ppm: self.ppm,
            pieces: self.pieces,
            ..EmbroiderParams::default()
        };
        // The ranges, checked before the job starts (the message names the field's flag).
        params.check()?;
        Ok(params)
    }
}

#[derive(Deserialize)]
pub(crate) struct EmbroiderRequest {
    file: Option<String>,
    #[serde(default)]
    params: EmbroiderForm,
}

/// Plans with more entries than this are summed up but not sent to be drawn (a 16 MB DST
/// holds ~5.6 million records: ~100 MB of JSON).
const MAX_DRAWN: usize = 2_000_000;

fn drawable(plan: &StitchPlan, file: &str) -> Result<(), CamError> {
    let n: usize = plan.blocks.iter().map(|b| b.stitches.len()).sum();
    if n > MAX_DRAWN {
        return Err(bad(format!(
            "{file}: {n} stitch entries is more than the {MAX_DRAWN} the page draws; `oficina embroider --info {file}` gives its sheet"
        )));
    }
    Ok(())
}

/// The plan in sewing order: per colour block its thread and its points as flat
/// `[x, y, kind, …]` (kind 0 stitch, 1 jump, 2 trim, 3 stop), mm.
pub(crate) fn plan_json(plan: &StitchPlan) -> Value {
    let blocks: Vec<Value> = plan
        .blocks
        .iter()
        .map(|b| {
            let mut points = Vec::with_capacity(b.stitches.len() * 3);
            for s in &b.stitches {
                let kind = match s.kind {
                    Kind::Stitch => 0,
                    Kind::Jump => 1,
                    Kind::Trim => 2,
                    Kind::Stop => 3,
                };
                // 0.01 mm is finer than any format's 0.1 mm unit: a smaller answer.
                points.push(json!((s.x * 100.0).round() / 100.0));
                points.push(json!((s.y * 100.0).round() / 100.0));
                points.push(json!(kind));
            }
            json!({"thread": b.thread.hex(), "name": b.thread.name, "points": points})
        })
        .collect();
    json!({"name": plan.name, "blocks": blocks})
}

fn sheet_json(s: &Sheet) -> Value {
    let c = &s.counts;
    let r = &s.run;
    let faults: Vec<Value> = r
        .faults
        .iter()
        .take(20)
        .map(|f| {
            json!({"stitch": f.index + 1, "colour": f.block + 1, "length": f.length, "ppm": f.ppm,
                   "move_ms": f.move_seconds * 1000.0, "window_ms": f.window_seconds * 1000.0})
        })
        .collect();
    json!({
        "stitches": c.stitches,
        "jumps": c.jumps,
        "trims": c.trims,
        "stops": c.stops,
        "color_changes": c.color_changes,
        "jump_length": c.jump_length,
        "threads": s.threads.iter().map(|t| json!({"hex": t.hex, "name": t.name, "stitches": t.stitches, "length_m": t.length_m})).collect::<Vec<_>>(),
        "thread_m": s.threads.iter().map(|t| t.length_m).sum::<f64>(),
        "size": s.size,
        "hoop": s.hoop.as_ref().map(|h| h.to_string()).ok(),
        "hoop_error": s.hoop.as_ref().err().map(|e| e.to_string()),
        "table": s.table,
        "pieces": s.pieces,
        "run": {
            "sewing_seconds": r.sewing_seconds,
            "jump_seconds": r.jump_seconds,
            "pause_seconds": r.pause_seconds,
            "total_seconds": r.total_seconds,
            "faults": r.faults.len(),
            "first_faults": faults,
            "out_of_travel": r.out_of_travel.len(),
            "too_long": r.too_long,
            "finished": r.faults.is_empty() && r.out_of_travel.is_empty(),
        },
        "text": s.text(),
    })
}

/// The design drawn as thread (`NAME.png`) and the printable A4 production sheet with that
/// render (`NAME.sheet.html`), written beside the stitch file in the job folder; their names,
/// or null where the render could not be made (the sheet is then written without it).
async fn render_files(st: &AppState, name: &str, plan: &StitchPlan, sheet: &Sheet) -> Value {
    let o = oficina_stitch::RenderOptions {
        dpi: 150.0,
        max_side: 2400,
        ..Default::default()
    };
    let png = oficina_stitch::render_png(plan, &o).ok();
    let page = sheet_document_with_render(std::path::Path::new("x.html"), sheet, plan);
    let mut out = json!({"render": null, "sheet_page": null});
    if let Some(png) = png {
        let n = format!("{name}.png");
        if let Ok(path) = path_in(&st.config.job_dir, &n) {
            if tokio::fs::write(&path, png).await.is_ok() {
                out["render"] = json!(n);
            }
        }
    }
    let n = format!("{name}.sheet.html");
    if let Ok(path) = path_in(&st.config.job_dir, &n) {
        if tokio::fs::write(&path, page).await.is_ok() {
            out["sheet_page"] = json!(n);
        }
    }
    out
}

/// The file name of lettering sewn alone: its letters and digits, the rest as `-` ("Ana|Maria"
/// → "Ana-Maria"), or `lettering`.
fn lettering_name(text: &str) -> String {
    let s: String = text
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '-' })
        .take(40)
        .collect();
    let s = s.trim_matches('-').to_string();
    if s.is_empty() {
        "lettering".into()
    } else {
        s
    }
}

/// `POST /api/embroider {file, params}`: the design → stitches → the file in the job folder.
pub(crate) async fn embroider_job(
    State(st): State<Arc<AppState>>,
    Json(req): Json<EmbroiderRequest>,
) -> Result<Response, CamError> {
    let text = req.params.text()?;
    // Text alone (no design file) is lettered by itself, as `oficina embroider --text`.
    let path = match (&req.file, &text) {
        (None, Some(_)) => None,
        _ => Some(input(&st, &req.file)?),
    };
    let file = req
        .file
        .clone()
        .unwrap_or_else(|| lettering_name(&req.params.text));
    let params = req.params.params()?;
    let name = output_name(&file, params.format.extension())?;
    let p = params.clone();
    let r = compute(&st, move |fb| {
        embroider_text(path.as_deref(), text.as_ref(), &p, fb)
    })
    .await?;
    if let Err(e) = &r.sheet.hoop {
        // As the CLI: nothing written for a design that leaves its hoop.
        return Err(bad(format!(
            "--hoop: {e}; nothing written (choose a larger hoop or scale the design)"
        )));
    }
    let out = path_in(&st.config.job_dir, &name).map_err(bad)?;
    tokio::fs::write(&out, &r.file)
        .await
        .map_err(|e| bad(format!("{name}: {e}")))?;
    // The plan as the file holds it (what the machine will sew), in the design's threads:
    // the file itself carries no colours.
    let mut plan = read_stitch_file(&out)?;
    for (b, g) in plan.blocks.iter_mut().zip(&r.generated.plan.blocks) {
        b.thread = g.thread.clone();
    }
    drawable(&plan, &name)?;
    let g = &r.generated;
    st.say(&format!(
        "embroidered {file} into {name} ({} stitches, {} colours)",
        r.sheet.counts.stitches,
        r.sheet.threads.len()
    ));
    let files = render_files(&st, &name, &plan, &r.sheet).await;
    Ok(Json(json!({
        "name": name,
        "bytes": r.file.len(),
        "format": params.format.name(),
        "shapes": {"fill": g.fills, "satin": g.satins, "running": g.runnings},
        "notes": r.notes,
        "plan": plan_json(&plan),
        "sheet": sheet_json(&r.sheet),
        "render": files["render"],
        "sheet_page": files["sheet_page"],
    }))
    .into_response())
}

/// `POST /api/stitches {file, params}`: a DST/EXP/RAM file of the job folder read back, its
/// sheet, and its run on the table the params name (`machine`, `ppm`, `hoop`, `pieces`).
pub(crate) async fn stitch_file(
    State(st): State<Arc<AppState>>,
    Json(req): Json<EmbroiderRequest>,
) -> Result<Response, CamError> {
    let path = input(&st, &req.file)?;
    let params = req.params.params()?;
    let (plan, sheet) = compute(&st, move |fb| {
        fb.stage("reading the stitch file")?;
        let plan = read_stitch_file(&path)?;
        if plan.is_empty() {
            return Err(Error(format!(
                "{}: the file holds no stitches",
                path.display()
            )));
        }
        fb.stage("sheet and table run")?;
        let sheet = sheet_of(&plan, &params)?;
        Ok((plan, sheet))
    })
    .await?;
    let file = req.file.unwrap_or_default();
    drawable(&plan, &file)?;
    st.say(&format!(
        "read {file}: {} stitches; on {}: {}",
        sheet.counts.stitches,
        sheet.table,
        if sheet.run.faults.is_empty() {
            "every stitch within its needle-up window".to_string()
        } else {
            format!(
                "{} stitch(es) too long for their window",
                sheet.run.faults.len()
            )
        }
    ));
    let files = render_files(&st, &file, &plan, &sheet).await;
    Ok(Json(json!({
        "name": file,
        "plan": plan_json(&plan),
        "sheet": sheet_json(&sheet),
        "render": files["render"],
        "sheet_page": files["sheet_page"],
    }))
    .into_response())
}
