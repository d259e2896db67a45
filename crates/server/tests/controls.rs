//! The machine panel's controls through the server: typed lines answered on every page's
//! console, work offsets in the status, macros kept in the job folder and run by name.

mod common;

use axum::body::Body;
use axum::http::{Request, StatusCode};
use common::{call, connect, send, until};
use serde_json::{json, Value};

fn put_macros(v: Value) -> Request<Body> {
    Request::put("/api/macros")
        .header("content-type", "application/json")
        .body(Body::from(v.to_string()))
        .unwrap()
}

#[tokio::test]
async fn macros_are_checked_and_kept_in_the_job_folder() {
    let dir = tempfile::tempdir().unwrap();
    let st = common::state(dir.path());
    let (s, v) = call(
        &st,
        Request::get("/api/macros").body(Body::empty()).unwrap(),
    )
    .await;
    assert_eq!((s, v["macros"].clone()), (StatusCode::OK, json!([])));
    let (s, v) = call(
        &st,
        put_macros(json!([{"name": "a", "text": "G0 X[nope]"}])),
    )
    .await;
    assert_eq!(s, StatusCode::BAD_REQUEST);
    assert!(
        v["error"]
            .as_str()
            .unwrap()
            .contains("unknown parameter [nope]"),
        "{v}"
    );
    let (s, _) = call(&st, put_macros(json!({"name": "not a list"}))).await;
    assert_eq!(s, StatusCode::BAD_REQUEST);
    let (s, v) = call(
        &st,
        put_macros(json!([{"name": "right", "text": "G0 X[x+1]"}])),
    )
    .await;
    assert_eq!(s, StatusCode::OK, "{v}");
    let saved = std::fs::read_to_string(dir.path().join("jobs/macros.json")).unwrap();
    assert!(saved.contains("G0 X[x+1]"), "{saved}");
}

fn status(want: impl Fn(&Value) -> bool) -> impl Fn(&Value) -> bool {
    move |m| m["type"] == "status" && want(&m["status"])
}

/// Work X of a status, within a micrometre of `x`.
fn work_x(s: &Value, x: f64) -> bool {
    s["work_pos"][0]
        .as_f64()
        .is_some_and(|v| (v - x).abs() < 1e-6)
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn typed_lines_offsets_and_macros_on_the_virtual_machine() {
    let dir = tempfile::tempdir().unwrap();
    let addr = common::serve(common::config(dir.path())).await;
    let mut a = connect(addr).await;
    let hello = until(&mut a, |m| m["type"] == "hello").await;
    assert_eq!(hello["controller"], true);
    let mut b = connect(addr).await;
    until(&mut b, |m| m["type"] == "hello").await;
    // A typed line: its echo and `ok` reach every page.
    let r = send(&mut a, json!({"cmd": "mdi", "line": "G0 X5 Y3"})).await;
    assert_eq!(r["type"], "ok", "{r}");
    let c = until(&mut b, |m| {
        m["type"] == "console" && m["lines"][0] == "> G0 X5 Y3"
    })
    .await;
    assert_eq!(c["lines"][0], "> G0 X5 Y3");
    until(&mut b, |m| m["type"] == "console" && m["lines"][0] == "ok").await;
    // `$` lines are not the virtual machine's: refused with the reason.
    let r = send(&mut a, json!({"cmd": "mdi", "line": "$$"})).await;
    assert!(
        r["message"].as_str().unwrap().contains("no firmware $"),
        "{r}"
    );
    // G55 chosen and zeroed: the status carries the table.
    assert_eq!(
        send(&mut a, json!({"cmd": "select_system", "system": 1})).await["type"],
        "ok"
    );
    assert_eq!(
        send(&mut a, json!({"cmd": "zero", "axes": [true, true, true]})).await["type"],
        "ok"
    );
    let s = until(
        &mut a,
        status(|s| s["offsets"]["active"] == 1 && work_x(s, 0.0)),
    )
    .await;
    let g55 = &s["status"]["offsets"]["systems"][1];
    assert_eq!(g55, &s["status"]["machine_pos"], "{s}");
    let r = send(&mut a, json!({"cmd": "select_system", "system": 9})).await;
    assert!(r["message"].as_str().unwrap().contains("G59"), "{r}");
    // A macro by name, its parameters from where the machine is.
    let req = put_macros(json!([{"name": "right", "text": "G0 X[x+2]"}]));
    let st = common::state(dir.path()); // (same folder: the file is what counts)
    assert_eq!(call(&st, req).await.0, StatusCode::OK);
    let r = send(&mut a, json!({"cmd": "run_macro", "name": "right"})).await;
    assert_eq!(r["type"], "ok", "{r}");
    until(&mut a, status(|s| work_x(s, 2.0))).await;
    let r = send(&mut a, json!({"cmd": "run_macro", "name": "left"})).await;
    assert!(
        r["message"].as_str().unwrap().contains("no macro named"),
        "{r}"
    );
    // Go to zero and home answer; reset is harmless when idle.
    assert_eq!(
        send(&mut a, json!({"cmd": "go_to_zero", "z": false})).await["type"],
        "ok"
    );
    until(&mut a, status(|s| s["state"] == "idle" && work_x(s, 0.0))).await;
    assert_eq!(
        send(&mut a, json!({"cmd": "soft_reset"})).await["type"],
        "ok"
    );
}
