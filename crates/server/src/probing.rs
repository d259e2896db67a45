//! The page's homing, probing, tool-change and levelling requests: their fields read into the
//! library's parameters, the session's routines started under its lock and waited for
//! outside it on a thread of their own (the request is answered at once: the page's socket
//! keeps carrying status and its Hold / Stop meanwhile), and what they measured sent to
//! every page as a `probing` message. The height map lives in the job folder as `level-map.json`.

use crate::state::lock;
use crate::AppState;
use oficina_app::{load_map, save_map, JobRequest, ProbeRequest, Probing, ProbingResult};
use oficina_grbl::{
    setter_at, Approach, Corner, GridSpec, HeightMap, ProbeMotion, ToolChange, ToolSetter, ZPlate,
};
use serde::Deserialize;
use serde_json::json;
use std::sync::Arc;

/// The height map's file in the job folder.
pub(crate) const MAP_FILE: &str = "level-map.json";

/// How a surface is approached (every routine's search and touch).
#[derive(Deserialize)]
pub(crate) struct ApproachArgs {
    travel: f64,
    feed: f64,
    slow_feed: f64,
    retract: f64,
}

impl From<&ApproachArgs> for Approach {
    fn from(a: &ApproachArgs) -> Approach {
        Approach {
            travel: a.travel,
            feed: a.feed,
            slow_feed: a.slow_feed,
            retract: a.retract,
        }
    }
}

#[derive(Deserialize)]
pub(crate) struct ZPlateArgs {
    thickness: f64,
    wcs: u8,
    #[serde(flatten)]
    approach: ApproachArgs,
}

#[derive(Deserialize)]
pub(crate) struct CornerArgs {
    thickness: f64,
    side_offset: [f64; 2],
    tool_diameter: f64,
    reach: f64,
    depth: f64,
    wcs: u8,
    #[serde(flatten)]
    approach: ApproachArgs,
}

#[derive(Deserialize)]
pub(crate) struct SetterArgs {
    /// Machine X, Y of the setter; none: where the tool is.
    at: Option<[f64; 2]>,
    safe_z: f64,
    reference: Option<f64>,
    #[serde(flatten)]
    approach: ApproachArgs,
}

#[derive(Deserialize)]
pub(crate) struct ToolChangeArgs {
    /// pause, park, remeasure, ignore or firmware.
    policy: String,
    /// Machine X, Y, Z of the park position.
    park: Option<[f64; 3]>,
    /// Machine X, Y of the tool setter and the Z its probing starts from.
    setter: Option<[f64; 3]>,
}

#[derive(Deserialize)]
pub(crate) struct LevelArgs {
    /// The program whose feed moves the grid covers (a job folder file or a sample).
    file: String,
    nx: usize,
    ny: usize,
    margin: f64,
    clearance: f64,
    depth: f64,
    feed: f64,
}

/// Waits for a routine outside the session's lock, then tells every page what it did.
fn finish(st: &Arc<AppState>, what: &'static str, r: Probing<ProbingResult>) {
    let st = st.clone();
    st.say(&format!("{what}: probing…"));
    std::thread::spawn(move || report(&st, what, r.wait()));
}

fn report(st: &AppState, what: &str, r: Result<ProbingResult, oficina_app::Error>) {
    // A routine sets work offsets (G10 L20) or the probe's last touch: the page's table is
    // read again, whatever the outcome (a board in alarm still answers `$#`).
    let _ = st.with_session(|s| s.read_offsets().map_err(|e| e.to_string()));
    match r {
        Ok(result) => {
            st.say(&format!("{what}: {}", describe(&result)));
            let _ = st
                .live
                .send(json!({"type": "probing", "result": result}).to_string());
        }
        Err(e) => {
            failed(st, &format!("{what} failed: {e}"));
        }
    }
}

fn failed(st: &AppState, message: &str) {
    st.say(message);
    let _ = st
        .live
        .send(json!({"type": "probing", "error": message}).to_string());
}

fn describe(r: &ProbingResult) -> String {
    let xyz = |p: &[f64; 3]| format!("X{:.3} Y{:.3} Z{:.3}", p[0], p[1], p[2]);
    match r {
        ProbingResult::Offset {
            contacts,
            wcs,
            offset,
            ..
        } => format!(
            "contact at machine {}; {wcs} offset now {}",
            contacts.iter().map(xyz).collect::<Vec<_>>().join(", "),
            xyz(offset)
        ),
        ProbingResult::Setter {
            contact,
            tool_offset,
            ..
        } => match tool_offset {
            Some(t) => format!(
                "setter touched at machine {}; tool length offset G43.1 Z{t:.3}",
                xyz(contact)
            ),
            None => format!(
                "setter touched at machine {} (a reference for later tools)",
                xyz(contact)
            ),
        },
    }
}

/// Homes: on firmware the cycle runs on the device's thread and is waited for outside the
/// session's lock (status keeps flowing, any page's Stop reaches it); how it ended goes to
/// every page's console, a failure as an error too.
pub(crate) fn home(st: &Arc<AppState>) -> Result<(), String> {
    let Some(cycle) = st.with_session(|s| s.home().map_err(|e| e.to_string()))? else {
        return Ok(());
    };
    st.say("home: homing cycle ($H)…");
    let st = st.clone();
    std::thread::spawn(move || match cycle.wait() {
        Ok(()) => {
            // grbl keeps the offsets over homing, but a failed or reset cycle may not.
            let _ = st.with_session(|s| s.read_offsets().map_err(|e| e.to_string()));
            st.say("home: homed");
        }
        Err(e) => {
            st.say(&format!("home: {e}"));
            let _ = st
                .live
                .send(json!({"type": "error", "message": e.to_string()}).to_string());
        }
    });
    Ok(())
}

pub(crate) fn z_plate(st: &Arc<AppState>, a: ZPlateArgs) -> Result<(), String> {
    let p = ZPlate {
        thickness: a.thickness,
        wcs: a.wcs,
        approach: (&a.approach).into(),
    };
    let r = st.with_session(|s| s.probe_z_plate(p).map_err(|e| e.to_string()))?;
    finish(st, "touch plate", r);
    Ok(())
}

pub(crate) fn corner(st: &Arc<AppState>, a: CornerArgs) -> Result<(), String> {
    let p = Corner {
        thickness: a.thickness,
        side_offset: a.side_offset,
        tool_diameter: a.tool_diameter,
        reach: a.reach,
        depth: a.depth,
        wcs: a.wcs,
        approach: (&a.approach).into(),
    };
    let r = st.with_session(|s| s.probe_corner(p).map_err(|e| e.to_string()))?;
    finish(st, "corner", r);
    Ok(())
}

pub(crate) fn setter(st: &Arc<AppState>, a: SetterArgs) -> Result<(), String> {
    let p = ToolSetter {
        at: a.at,
        safe_z: a.safe_z,
        reference: a.reference,
        approach: (&a.approach).into(),
    };
    let r = st.with_session(|s| s.probe_setter(p).map_err(|e| e.to_string()))?;
    finish(st, "tool length setter", r);
    Ok(())
}

pub(crate) fn tool_change(st: &AppState, a: ToolChangeArgs) -> Result<(), String> {
    let tc = ToolChange {
        policy: a.policy.parse()?,
        park: a.park,
        setter: a.setter.map(|[x, y, z]| setter_at(x, y, z)),
        measure_at_start: false,
    };
    st.with_session(|s| s.set_tool_change(tc).map_err(|e| e.to_string()))
}

/// Probes the grid over the program, saves the map in the job folder and sends it.
pub(crate) fn probe_map(st: &Arc<AppState>, a: LevelArgs) -> Result<(), String> {
    for (what, n) in [("nx", a.nx), ("ny", a.ny)] {
        if !(2..=oficina_grbl::MAX_GRID).contains(&n) {
            return Err(format!(
                "{what} {n}: a grid has 2 … {} points along each axis",
                oficina_grbl::MAX_GRID
            ));
        }
    }
    if !(a.margin.is_finite() && (0.0..=1000.0).contains(&a.margin)) {
        return Err(format!("margin {}: 0 … 1000 mm", a.margin));
    }
    let text = crate::api::program_text(st, &a.file).map_err(|(_, m)| m)?;
    let req = ProbeRequest {
        grid: GridSpec::Count(a.nx, a.ny),
        area: None,
        margin: a.margin,
        motion: ProbeMotion {
            clearance: a.clearance,
            max_depth: a.depth,
            feed: a.feed,
        },
    };
    let r = st.with_session(|s| {
        s.probe_height_map(text.to_string(), req)
            .map_err(|e| e.to_string())
    })?;
    st.say(&format!(
        "probing a {} × {} height map over {}",
        a.nx, a.ny, a.file
    ));
    let st = st.clone();
    std::thread::spawn(move || {
        let saved = r.wait().and_then(|map| {
            save_map(&st.config.job_dir.join(MAP_FILE), &map)?;
            Ok(map)
        });
        match saved {
            Ok(map) => {
                let (lo, hi) = map.z_range();
                st.say(&format!(
                    "height map saved to {MAP_FILE}: Z {lo:.3} … {hi:.3} ({:.3} mm)",
                    hi - lo
                ));
                send_map(&st, &map);
            }
            Err(e) => failed(&st, &format!("height map failed: {e}")),
        }
    });
    Ok(())
}

/// The saved map, sent to every page.
pub(crate) fn load(st: &AppState) -> Result<(), String> {
    let map = saved_map(st)?;
    st.say(&format!("height map loaded from {MAP_FILE}"));
    send_map(st, &map);
    Ok(())
}

fn saved_map(st: &AppState) -> Result<HeightMap, String> {
    let path = st.config.job_dir.join(MAP_FILE);
    if !path.is_file() {
        return Err(format!(
            "no height map in the job folder ({MAP_FILE}): probe one first"
        ));
    }
    load_map(&path).map_err(|e| e.to_string())
}

fn send_map(st: &AppState, map: &HeightMap) {
    let value: serde_json::Value = serde_json::from_str(&map.to_json()).unwrap_or_default();
    let _ = st
        .live
        .send(json!({"type": "height_map", "map": value}).to_string());
}

/// Starts `file` levelled with the saved map.
pub(crate) fn start_levelled(
    st: &AppState,
    file: String,
    from_line: Option<u32>,
) -> Result<(), String> {
    let map = saved_map(st)?;
    let text = crate::api::program_text(st, &file).map_err(|(_, m)| m)?;
    let job = crate::state::RunningJob {
        name: file.clone(),
        text: text.clone(),
    };
    let report = st.with_session(|s| {
        s.start_levelled(
            JobRequest {
                name: file.clone(),
                text,
                from_line,
                speed: None,
            },
            &map,
        )
        .map_err(|e| e.to_string())
    })?;
    let (lo, hi) = report.offset_range;
    st.say(&format!(
        "started {file} levelled with {MAP_FILE}: {} moves levelled, Z offsets {lo:.3} … {hi:.3}",
        report.levelled_moves
    ));
    for w in &report.warnings {
        st.say(&format!("levelling: {w}"));
    }
    *lock(&st.job) = Some(job);
    Ok(())
}
