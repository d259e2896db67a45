//! The tool table saved in the page reaches the check (G43 H lengths, G41 D diameters, each
//! used tool's data) and the virtual machine's run; a broken saved table is named, never
//! silently dropped.

mod common;

use axum::body::Body;
use axum::http::{Request, StatusCode};
use common::{call, config, send, until, Ws};
use oficina_server::AppState;
use serde_json::{json, Value};
use std::sync::Arc;

const TABLE: &str = "T1 P1 D6 Z12.5 ;flat 6\n";
/// Tool 1's length offset on, then a square cut with the tool's radius to its left.
const PROGRAM: &str = "G21 G90 G17 G54\nT1 M6\nG43 H1\nG0 X0 Y0 Z5\nG1 Z-1 F100\nG41 D1\nG1 X10 Y0 F600\nX10 Y10\nG40\nG0 Z5\nM2\n";

async fn check(st: &Arc<AppState>) -> (StatusCode, Value) {
    call(
        st,
        Request::post("/api/check")
            .body(Body::from(PROGRAM))
            .unwrap(),
    )
    .await
}

#[tokio::test]
async fn the_saved_tool_table_reaches_the_check() {
    let dir = tempfile::tempdir().unwrap();
    let st = AppState::new(config(dir.path())).unwrap();
    let (s, bare) = check(&st).await;
    assert_eq!(s, StatusCode::OK, "{bare}");
    assert_eq!(bare["tool_table"], json!([]));
    let (s, v) = call(
        &st,
        Request::put("/api/tools").body(Body::from(TABLE)).unwrap(),
    )
    .await;
    assert_eq!(s, StatusCode::OK, "{v}");
    let (s, with) = check(&st).await;
    assert_eq!(s, StatusCode::OK, "{with}");
    assert_eq!(with["errors"], 0, "{with}");
    let z = |r: &Value| r["feed_extents"]["min"][2].as_f64().unwrap();
    let x = |r: &Value| r["feed_extents"]["max"][0].as_f64().unwrap();
    // G43 H1: every Z 12.5 mm higher; G41 D1: the leg up X10 cut 3 mm to its left.
    assert!((z(&with) - z(&bare) - 12.5).abs() < 1e-9, "{with} {bare}");
    assert!((x(&bare) - x(&with) - 3.0).abs() < 1e-6, "{with} {bare}");
    assert_eq!(with["tool_table"][0][0], 1);
    assert_eq!(with["tool_table"][0][1]["diameter"], 6.0);
    assert_eq!(with["tool_table"][0][1]["length"], 12.5);

    // Bad input: a table written past the editor (as any file of the job folder) that the
    // interpreter cannot read is named with its line, not ignored.
    let (s, _) = call(
        &st,
        Request::put("/api/files/tool.tbl")
            .body(Body::from("T1 P1 D6\nT2 P2 Dx\n"))
            .unwrap(),
    )
    .await;
    assert_eq!(s, StatusCode::OK);
    let (s, v) = check(&st).await;
    assert_eq!(s, StatusCode::BAD_REQUEST, "{v}");
    let msg = v.as_str().unwrap();
    assert!(msg.contains("tool.tbl line 2"), "{msg}");
    let (s, _) = call(
        &st,
        Request::put("/api/files/tool.tbl")
            .body(Body::from(vec![0xff, 0xfe, 0x00]))
            .unwrap(),
    )
    .await;
    assert_eq!(s, StatusCode::OK);
    let (s, v) = check(&st).await;
    assert_eq!(s, StatusCode::BAD_REQUEST, "{v}");
    assert!(v.as_str().unwrap().contains("UTF-8"), "{v}");
}

/// Runs `file` to its end and gives the machine position where it stopped.
async fn run(ws: &mut Ws, file: &str) -> [f64; 3] {
    let r = send(ws, json!({"cmd": "start", "file": file})).await;
    assert_eq!(r["type"], "ok", "{r}");
    let end = until(ws, |m| {
        m["type"] == "event" && m["event"]["type"] == "job_end"
    })
    .await;
    assert_eq!(end["event"]["completed"], true, "{end}");
    let s = until(ws, |m| {
        m["type"] == "status"
            && m["status"]["state"] == "idle"
            && m["status"]["job"]["completed"] == true
    })
    .await;
    let p = &s["status"]["machine_pos"];
    [0, 1, 2].map(|i| p[i].as_f64().unwrap())
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_virtual_machine_runs_with_the_saved_tool_table() {
    let dir = tempfile::tempdir().unwrap();
    let cfg = config(dir.path());
    let jobs = cfg.job_dir.clone();
    let addr = common::serve(cfg).await;
    std::fs::write(jobs.join("square.nc"), PROGRAM).unwrap();
    // The same end point without the tool's offset (no table: G43 H1 would be refused).
    std::fs::write(jobs.join("plain.nc"), "G21 G90 G54\nG0 X0 Y0 Z5\nM2\n").unwrap();
    let mut ws = common::connect(addr).await;
    until(&mut ws, |m| m["type"] == "hello").await;
    let bare = run(&mut ws, "plain.nc").await;
    // Saved as the editor saves it (PUT /api/tools writes this file once checked).
    std::fs::write(jobs.join("tool.tbl"), TABLE).unwrap();
    let with = run(&mut ws, "square.nc").await;
    // The job ends at Z5 after G43 H1: 12.5 mm higher in machine coordinates.
    assert!(
        (with[2] - bare[2] - 12.5).abs() < 1e-6,
        "{with:?} vs {bare:?}"
    );
    // A broken saved table stops the start with its place, and nothing runs.
    std::fs::write(jobs.join("tool.tbl"), "T1 P1 Dx\n").unwrap();
    let r = send(&mut ws, json!({"cmd": "start", "file": "square.nc"})).await;
    assert_eq!(r["type"], "error", "{r}");
    assert!(
        r["message"].as_str().unwrap().contains("tool.tbl line 1"),
        "{r}"
    );
}
