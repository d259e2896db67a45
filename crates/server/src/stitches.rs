//! The stitch editor's endpoints: an embroidery file of the job folder opened as a plan, a
//! plan altered (scale, rotate, mirror, shift: `oficina_stitch::alter`), several linked into
//! one (`link`, each placed by its offset), a section sewn at a faster speed code
//! (`sew_at_speed`), and a plan saved in a format the library writes. The page edits the plan
//! itself (move, insert, delete, colour stops) and sends it back whole; every answer carries
//! the plan and its sections with the speed code the machine picks for each.

use crate::embroider::plan_json;
use crate::files::path_in;
use crate::jobs::{bad, input, CamError};
use crate::AppState;
use axum::extract::State;
use axum::response::{IntoResponse, Response};
use axum::Json;
use oficina_app::embroider::read_stitch_file;
use oficina_stitch::{
    alter, link, sections, sew_at_speed, Alteration, ColorBlock, Format, Kind, MirrorAxis, Stitch,
    StitchPlan, Thread, MAX_STITCHES,
};
use serde::Deserialize;
use serde_json::{json, Value};
use std::sync::Arc;

/// Points farther than this from the origin (mm) are no embroidery: the largest hoops are
/// under half a metre.
const MAX_COORD: f64 = 10_000.0;

/// A plan as the page sends it: `plan_json`'s form (flat `[x, y, kind, …]` per block).
#[derive(Deserialize)]
pub(crate) struct PlanIn {
    #[serde(default)]
    name: String,
    blocks: Vec<BlockIn>,
}

#[derive(Deserialize)]
struct BlockIn {
    thread: String,
    #[serde(default)]
    name: String,
    points: Vec<f64>,
}

fn thread_of(hex: &str, name: &str, b: usize) -> Result<Thread, String> {
    let h = hex.trim_start_matches('#');
    let byte = |i: usize| h.get(i..i + 2).and_then(|s| u8::from_str_radix(s, 16).ok());
    match (h.len(), byte(0), byte(2), byte(4)) {
        (6, Some(r), Some(g), Some(bl)) => Ok(Thread {
            rgb: [r, g, bl],
            name: name.to_string(),
        }),
        _ => Err(format!("block {}: thread {hex:?} is not #rrggbb", b + 1)),
    }
}

impl PlanIn {
    /// The plan, or what is wrong with it and where (block, entry).
    fn plan(self) -> Result<StitchPlan, CamError> {
        let total: usize = self.blocks.iter().map(|b| b.points.len() / 3).sum();
        if total > MAX_STITCHES {
            return Err(bad(format!(
                "the plan has {total} entries, more than the {MAX_STITCHES} a design may have"
            )));
        }
        let mut blocks = Vec::with_capacity(self.blocks.len());
        for (b, block) in self.blocks.into_iter().enumerate() {
            let thread = thread_of(&block.thread, &block.name, b).map_err(bad)?;
            if block.points.len() % 3 != 0 {
                return Err(bad(format!(
                    "block {}: {} numbers is no whole number of [x, y, kind] entries",
                    b + 1,
                    block.points.len()
                )));
            }
            let mut stitches = Vec::with_capacity(block.points.len() / 3);
            for (i, e) in block.points.chunks_exact(3).enumerate() {
                let kind = match if e[2].fract() == 0.0 { e[2] as i64 } else { -1 } {
                    0 => Kind::Stitch,
                    1 => Kind::Jump,
                    2 => Kind::Trim,
                    3 => Kind::Stop,
                    _ => {
                        return Err(bad(format!(
                            "block {}, entry {}: kind {} is not 0 (stitch), 1 (jump), 2 (trim) or 3 (stop)",
                            b + 1,
                            i + 1,
                            e[2]
                        )))
                    }
                };
                if !(e[0].abs() <= MAX_COORD && e[1].abs() <= MAX_COORD) {
                    return Err(bad(format!(
                        "block {}, entry {}: ({}, {}) mm is not a point within {MAX_COORD} mm",
                        b + 1,
                        i + 1,
                        e[0],
                        e[1]
                    )));
                }
                stitches.push(Stitch::new(e[0], e[1], kind));
            }
            blocks.push(ColorBlock { thread, stitches });
        }
        Ok(StitchPlan {
            name: self.name,
            blocks,
        })
    }
}

/// The answer: the plan and its sections `[start, end, code]` (code null: a stitch longer
/// than the machine sews).
fn answer(plan: &StitchPlan, extra: Value) -> Response {
    let secs: Vec<Value> = sections(plan)
        .iter()
        .map(|s| json!([s.start, s.end, s.code]))
        .collect();
    let mut v = json!({"plan": plan_json(plan), "sections": secs});
    if let (Value::Object(m), Value::Object(e)) = (&mut v, extra) {
        m.extend(e);
    }
    Json(v).into_response()
}

#[derive(Deserialize)]
pub(crate) struct OpenRequest {
    file: Option<String>,
}

/// `POST /api/stitches/open {file}`: an embroidery file of the job folder as a plan.
pub(crate) async fn open(
    State(st): State<Arc<AppState>>,
    Json(req): Json<OpenRequest>,
) -> Result<Response, CamError> {
    let path = input(&st, &req.file)?;
    let plan = read_stitch_file(&path)?;
    if plan.is_empty() {
        return Err(bad(format!(
            "{}: the file holds no stitches",
            req.file.unwrap_or_default()
        )));
    }
    Ok(answer(&plan, json!({})))
}

/// The alteration as `oficina embroider`'s flags give it (`--scale --rotate --mirror
/// --shift`).
#[derive(Deserialize)]
pub(crate) struct AlterRequest {
    plan: PlanIn,
    #[serde(default)]
    shift: [f64; 2],
    #[serde(default)]
    rotate: f64,
    /// "x" or "y"; absent: none.
    mirror: Option<String>,
    scale: Option<f64>,
}

/// `POST /api/stitches/alter {plan, shift, rotate, mirror, scale}`: the plan altered.
pub(crate) async fn alter_plan(Json(req): Json<AlterRequest>) -> Result<Response, CamError> {
    let mirror = match req.mirror.as_deref() {
        None | Some("") => None,
        Some("x") => Some(MirrorAxis::X),
        Some("y") => Some(MirrorAxis::Y),
        Some(m) => return Err(bad(format!("--mirror {m}: use x or y"))),
    };
    let a = Alteration {
        shift: req.shift,
        rotate_deg: req.rotate,
        mirror,
        scale: req.scale.unwrap_or(1.0),
    };
    a.check().map_err(bad)?;
    let plan = req.plan.plan()?;
    Ok(answer(&alter(&plan, &a), json!({})))
}

#[derive(Deserialize)]
pub(crate) struct Placed {
    plan: PlanIn,
    /// Where its origin goes, mm (the seed's Zero-Peça from Zero-Máquina).
    #[serde(default)]
    at: [f64; 2],
}

#[derive(Deserialize)]
pub(crate) struct LinkRequest {
    designs: Vec<Placed>,
}

/// `POST /api/stitches/link {designs: [{plan, at}]}`: the designs joined in order, one point
/// from each one's last stitch to the next one's origin.
pub(crate) async fn link_plans(Json(req): Json<LinkRequest>) -> Result<Response, CamError> {
    if req.designs.len() < 2 {
        return Err(bad("link: give two designs or more"));
    }
    let mut programs = Vec::with_capacity(req.designs.len());
    for (i, d) in req.designs.into_iter().enumerate() {
        if !d.at.iter().all(|v| v.abs() <= MAX_COORD) {
            return Err(bad(format!(
                "design {}: offset {:?} mm is not within {MAX_COORD} mm",
                i + 1,
                d.at
            )));
        }
        programs.push((d.plan.plan()?, d.at));
    }
    let n: usize = programs.iter().map(|(p, _)| p.entries().count() + 1).sum();
    if n > MAX_STITCHES {
        return Err(bad(format!(
            "link: {n} entries, more than the {MAX_STITCHES} a design may have"
        )));
    }
    Ok(answer(&link(&programs), json!({})))
}

#[derive(Deserialize)]
pub(crate) struct SpeedRequest {
    plan: PlanIn,
    /// An entry of the section, counted over the plan in sewing order.
    entry: usize,
    code: u8,
}

/// `POST /api/stitches/speed {plan, entry, code}`: the section of `entry` sewn at `code`.
pub(crate) async fn speed(Json(req): Json<SpeedRequest>) -> Result<Response, CamError> {
    let plan = req.plan.plan()?;
    let out = sew_at_speed(&plan, req.entry, req.code).map_err(bad)?;
    Ok(answer(&out, json!({})))
}

#[derive(Deserialize)]
pub(crate) struct SaveRequest {
    plan: PlanIn,
    /// The file name in the job folder; its extension names the format unless `format` does.
    name: String,
    format: Option<String>,
}

/// `POST /api/stitches/save {plan, name, format}`: the plan written by the library's writer
/// into the job folder; the answer carries the file read back (what the machine will sew).
pub(crate) async fn save(
    State(st): State<Arc<AppState>>,
    Json(req): Json<SaveRequest>,
) -> Result<Response, CamError> {
    let path = path_in(&st.config.job_dir, &req.name).map_err(bad)?;
    let format = oficina_app::embroider::output_format(
        Some(&path),
        match req.format.as_deref() {
            None | Some("") => None,
            Some(f) => {
                Some(Format::from_id(f).ok_or_else(|| bad(format!("--format {f}: unknown")))?)
            }
        },
    )?;
    let plan = req.plan.plan()?;
    if plan.is_empty() {
        return Err(bad("the design holds no stitches: nothing written"));
    }
    let bytes = format.write(&plan).map_err(|e| bad(e.to_string()))?;
    tokio::fs::write(&path, &bytes)
        .await
        .map_err(|e| bad(format!("{}: {e}", req.name)))?;
    let back = read_stitch_file(&path)?;
    let c = back.counts();
    st.say(&format!(
        "saved {} ({}, {} stitches, {} colours)",
        req.name,
        format.name(),
        c.stitches,
        back.blocks.len()
    ));
    Ok(answer(
        &back,
        json!({"name": req.name, "bytes": bytes.len(), "format": format.name(),
               "stitches": c.stitches, "colours": back.blocks.len()}),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(v: Value) -> Result<StitchPlan, String> {
        serde_json::from_value::<PlanIn>(v)
            .map_err(|e| e.to_string())?
            .plan()
            .map_err(|e| String::from_utf8_lossy(&body_of(e.into_response())).into_owned())
    }

    fn message(v: Value) -> String {
        let Err(e) = serde_json::from_value::<PlanIn>(v).unwrap().plan() else {
            panic!("accepted");
        };
        let r = e.into_response();
        let body = body_of(r);
        serde_json::from_slice::<Value>(&body).unwrap()["error"]
            .as_str()
            .unwrap()
            .to_string()
    }

    fn body_of(r: Response) -> Vec<u8> {
        let rt = tokio::runtime::Builder::new_current_thread()
            .build()
            .unwrap();
        rt.block_on(http_body_util::BodyExt::collect(r.into_body()))
            .unwrap()
            .to_bytes()
            .to_vec()
    }

    #[test]
    fn the_pages_plan_reads_back_as_sent_and_bad_entries_are_named() {
        let plan = StitchPlan {
            name: "p".into(),
            blocks: vec![
                ColorBlock {
                    thread: Thread::rgb(200, 10, 0),
                    stitches: vec![
                        Stitch::new(1.25, -3.5, Kind::Jump),
                        Stitch::new(2.0, 0.0, Kind::Stitch),
                        Stitch::new(2.0, 0.0, Kind::Trim),
                    ],
                },
                ColorBlock {
                    thread: Thread::rgb(0, 0, 255),
                    stitches: vec![Stitch::new(-7.5, 4.0, Kind::Stop)],
                },
            ],
        };
        assert_eq!(parse(plan_json(&plan)).unwrap(), plan);
        let one = |thread: &str, points: Value| {
            json!({"blocks": [{"thread": "#000000", "points": [0, 0, 0]},
                              {"thread": thread, "points": points}]})
        };
        assert!(message(one("red", json!([0, 0, 0]))).contains("block 2: thread \"red\""));
        assert!(message(one("#ff0000", json!([0, 0]))).contains("block 2: 2 numbers"));
        assert!(message(one("#ff0000", json!([0, 0, 0, 1, 1, 0.5])))
            .contains("block 2, entry 2: kind 0.5"));
        assert!(message(one("#ff0000", json!([0, 1e6, 0]))).contains("block 2, entry 1"));
    }
}
