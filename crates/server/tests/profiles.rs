//! The profile editor's endpoints: the motion crate's own validation messages come back
//! with their key; a good profile is put on the virtual machine.

mod common;

use axum::body::Body;
use axum::http::{Request, StatusCode};
use oficina_server::AppState;
use serde_json::Value;
use std::sync::Arc;

/// The router's answer to `req`: status and body as text.
async fn call(st: &Arc<AppState>, req: Request<Body>) -> (StatusCode, String) {
    let (status, body) = common::call_bytes(st, req).await;
    (status, String::from_utf8_lossy(&body).into())
}

#[tokio::test]
async fn profiles_are_checked_by_their_own_validation_and_used() {
    let dir = tempfile::tempdir().unwrap();
    let st = common::state(dir.path());
    let (s, text) = call(
        &st,
        Request::get("/api/profiles/grbl-router")
            .body(Body::empty())
            .unwrap(),
    )
    .await;
    assert_eq!(s, StatusCode::OK);
    assert!(
        text.contains("[travel]") || text.contains("travel"),
        "{text}"
    );
    let post = |uri: &str, body: String| Request::post(uri).body(Body::from(body)).unwrap();
    let (s, v) = call(&st, post("/api/profiles/check", text.clone())).await;
    assert_eq!(s, StatusCode::OK, "{v}");

    // Travel with min above max: the profile's own message, naming its key.
    let broken = text.replacen("x = [", "x = [9999, 0] # was [", 1);
    assert_ne!(broken, text, "the sample has an x travel line");
    let (s, v) = call(&st, post("/api/profiles/check", broken)).await;
    assert_eq!(s, StatusCode::BAD_REQUEST, "{v}");
    let v: Value = serde_json::from_str(&v).unwrap();
    assert_eq!(v["ok"], false);
    assert!(v["key"].as_str().unwrap().contains("travel"), "{v}");
    assert!(!v["error"].as_str().unwrap().is_empty());
    // Not TOML at all: the line is named.
    let (s, v) = call(&st, post("/api/profiles/check", "name = \n[".into())).await;
    assert_eq!(s, StatusCode::BAD_REQUEST);
    assert!(v.contains("line"), "{v}");
    assert_eq!(
        call(
            &st,
            Request::get("/api/profiles/nope")
                .body(Body::empty())
                .unwrap()
        )
        .await
        .0,
        StatusCode::NOT_FOUND
    );

    // Used: saved in the job folder, the virtual machine reconnected to it.
    let renamed = text.replacen("name = \"", "name = \"my router ", 1);
    let (s, v) = call(&st, post("/api/profiles/use", renamed)).await;
    assert_eq!(s, StatusCode::OK, "{v}");
    let v: Value = serde_json::from_str(&v).unwrap();
    assert!(v["uri"].as_str().unwrap().starts_with("virtual:"), "{v}");
    let snap = st.snapshot_json();
    assert!(
        snap["status"]["machine"]
            .as_str()
            .unwrap()
            .contains("my router"),
        "{snap}"
    );
    assert!(std::fs::read_dir(dir.path().join("jobs"))
        .unwrap()
        .flatten()
        .any(|e| e
            .file_name()
            .to_string_lossy()
            .starts_with("profile-my-router")));
}

#[tokio::test]
async fn the_tool_table_is_read_by_the_interpreter_and_saved_only_when_good() {
    let dir = tempfile::tempdir().unwrap();
    let st = common::state(dir.path());
    let put = |body: &str| {
        Request::put("/api/tools")
            .body(Body::from(body.to_string()))
            .unwrap()
    };
    let (s, v) = call(&st, put("T1 P1 D6 Z12.5 ;flat 6\nT2 P2 D3 Z20\n")).await;
    assert_eq!(s, StatusCode::OK, "{v}");
    let v: Value = serde_json::from_str(&v).unwrap();
    assert_eq!(v["tools"][0]["diameter"], 6.0);
    assert_eq!(v["tools"][1]["length"], 20.0);
    let (s, v) = call(&st, put("T1 P1 D6\nT2 P2 Dbad\n")).await;
    assert_eq!(s, StatusCode::BAD_REQUEST);
    let v: Value = serde_json::from_str(&v).unwrap();
    assert_eq!(v["line"], 2, "{v}");
    // The bad table did not replace the good one.
    let (s, text) = call(&st, Request::get("/api/tools").body(Body::empty()).unwrap()).await;
    assert_eq!(s, StatusCode::OK);
    assert!(text.starts_with("T1 P1 D6 Z12.5"), "{text}");
}
