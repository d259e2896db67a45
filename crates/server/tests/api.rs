//! The HTTP API and its bad inputs, through the router (no socket).

mod common;

use axum::body::Body;
use axum::http::{Request, StatusCode};
use common::call_bytes as call;
use oficina_server::{check_listen, AppState, Config};
use std::sync::Arc;
use tower::ServiceExt;

fn state(dir: &std::path::Path, token: Option<&str>, limit: usize) -> Arc<AppState> {
    AppState::new(Config {
        token: token.map(String::from),
        upload_limit: limit,
        ..common::config(dir)
    })
    .unwrap()
}

fn post(uri: &str, body: impl Into<Body>) -> Request<Body> {
    Request::post(uri).body(body.into()).unwrap()
}

fn json(b: &[u8]) -> serde_json::Value {
    serde_json::from_slice(b).unwrap_or_else(|e| panic!("{e}: {}", String::from_utf8_lossy(b)))
}

const SQUARE: &str = "G21 G90\nG0 X0 Y0 Z5\nG1 Z-1 F100\nG1 X10 F600\nY10\nX0\nY0\nG0 Z5\nM2\n";

#[tokio::test]
async fn check_reports_extents_time_and_diagnostics_with_places() {
    let dir = tempfile::tempdir().unwrap();
    let st = state(dir.path(), None, 1 << 20);
    let (s, b) = call(&st, post("/api/check", SQUARE)).await;
    assert_eq!(s, StatusCode::OK);
    let r = json(&b);
    assert_eq!(r["errors"], 0);
    assert!(
        (r["feed_length"].as_f64().unwrap() - 46.0).abs() < 1e-9,
        "{r}"
    );
    assert!(r["time"]["Ok"]["seconds"].as_f64().unwrap() > 7.6);

    let (s, b) = call(&st, post("/api/check", "G0 X0\nG1 X10 Qbad\nM2\n")).await;
    assert_eq!(s, StatusCode::OK);
    let r = json(&b);
    assert!(r["errors"].as_u64().unwrap() >= 1, "{r}");
    assert_eq!(r["diagnostics"][0]["line"], 2, "{r}");
    assert!(r["diagnostics"][0]["col"].as_u64().unwrap() >= 1);
}

#[tokio::test]
async fn preview_sends_whole_records_with_lines_and_kinds() {
    let dir = tempfile::tempdir().unwrap();
    let st = state(dir.path(), None, 1 << 20);
    let (s, b) = call(&st, post("/api/preview", SQUARE)).await;
    assert_eq!(s, StatusCode::OK);
    assert_eq!(b.len() % 28, 0);
    let recs: Vec<(u32, u32, [f32; 6])> = b
        .chunks(28)
        .map(|r| {
            let f = |i: usize| f32::from_le_bytes(r[4 * i..4 * i + 4].try_into().unwrap());
            let tag = u32::from_le_bytes(r[24..28].try_into().unwrap());
            (tag >> 2, tag & 3, [f(0), f(1), f(2), f(3), f(4), f(5)])
        })
        .collect();
    // rapid (line 2), plunge (3), four feeds (4-7), rapid (8)
    let kinds: Vec<(u32, u32)> = recs.iter().map(|r| (r.0, r.1)).collect();
    assert_eq!(
        kinds,
        [(2, 0), (3, 2), (4, 1), (5, 1), (6, 1), (7, 1), (8, 0)]
    );
    // The feed along X is 10 mm long.
    let p = recs[2].2;
    assert!((p[3] - p[0] - 10.0).abs() < 1e-4, "{p:?}");
}

#[tokio::test]
async fn bad_inputs_get_clear_errors() {
    let dir = tempfile::tempdir().unwrap();
    let st = state(dir.path(), None, 1000);
    // Not UTF-8.
    let (s, b) = call(&st, post("/api/check", vec![b'G', 0xff, 0xfe])).await;
    assert_eq!(s, StatusCode::BAD_REQUEST);
    assert!(String::from_utf8_lossy(&b).contains("UTF-8"));
    // Too big.
    let (s, _) = call(&st, post("/api/check", vec![b'\n'; 5000])).await;
    assert_eq!(s, StatusCode::PAYLOAD_TOO_LARGE);
    // Unknown dialect.
    let (s, b) = call(&st, post("/api/check?dialect=klingon", "G0 X1\n")).await;
    assert_eq!(s, StatusCode::BAD_REQUEST);
    assert!(String::from_utf8_lossy(&b).contains("klingon"));
    // A file that is not there, and a name that leaves the folder.
    let (s, _) = call(&st, post("/api/check?file=nothing.nc", "")).await;
    assert_eq!(s, StatusCode::NOT_FOUND);
    let (s, _) = call(&st, post("/api/check?file=..%2F..%2Fetc%2Fpasswd", "")).await;
    assert_eq!(s, StatusCode::BAD_REQUEST);
    // A carve of an empty image and of absurd parameters.
    let q = "name=x.png&width=50&depth=5&tool=ball:6&stepover=1&stepdown=5&feed=2000&plunge_feed=500&safe_z=5";
    let (s, b) = call(&st, post(&format!("/api/carve?{q}"), Vec::<u8>::new())).await;
    assert_eq!(s, StatusCode::BAD_REQUEST);
    assert!(
        String::from_utf8_lossy(&b).contains("x.png"),
        "{}",
        String::from_utf8_lossy(&b)
    );
    let q2 = q.replace("width=50", "width=-1");
    let (s, b) = call(&st, post(&format!("/api/carve?{q2}"), vec![1u8; 10])).await;
    assert_eq!(s, StatusCode::BAD_REQUEST);
    assert!(String::from_utf8_lossy(&b).contains("width"));
}

#[tokio::test]
async fn uploads_stay_in_the_job_folder() {
    let dir = tempfile::tempdir().unwrap();
    let st = state(dir.path(), None, 1 << 16);
    let put = |name: &str, body: &'static str| {
        Request::put(format!("/api/files/{name}"))
            .body(Body::from(body))
            .unwrap()
    };
    let (s, _) = call(&st, put("part.nc", SQUARE)).await;
    assert_eq!(s, StatusCode::OK);
    assert_eq!(
        std::fs::read_to_string(dir.path().join("jobs/part.nc")).unwrap(),
        SQUARE
    );
    for bad in ["..%2Fescape.nc", ".hidden", "a%5Cb.nc", "%2Fetc%2Fx"] {
        let (s, _) = call(&st, put(bad, "x")).await;
        assert_eq!(s, StatusCode::BAD_REQUEST, "{bad}");
    }
    assert!(!dir.path().join("escape.nc").exists());
    let (s, b) = call(&st, Request::get("/api/files").body(Body::empty()).unwrap()).await;
    assert_eq!(s, StatusCode::OK);
    assert_eq!(json(&b), serde_json::json!(["part.nc"]));
    // Checked by name from the folder.
    let (s, b) = call(&st, post("/api/check?file=part.nc", "")).await;
    assert_eq!(s, StatusCode::OK);
    assert_eq!(json(&b)["feed_moves"], 5);
}

#[tokio::test]
async fn a_token_guards_the_api_but_not_the_page() {
    let dir = tempfile::tempdir().unwrap();
    let st = state(dir.path(), Some("0123456789abcdef"), 1 << 16);
    let get = |uri: &str| Request::get(uri).body(Body::empty()).unwrap();
    assert_eq!(
        call(&st, get("/api/info")).await.0,
        StatusCode::UNAUTHORIZED
    );
    assert_eq!(
        call(&st, get("/api/info?token=wrong-wrong-wrong")).await.0,
        StatusCode::UNAUTHORIZED
    );
    assert_eq!(
        call(&st, get("/api/info?token=0123456789abcdef")).await.0,
        StatusCode::OK
    );
    let with_header = Request::get("/api/info")
        .header("Authorization", "Bearer 0123456789abcdef")
        .body(Body::empty())
        .unwrap();
    assert_eq!(call(&st, with_header).await.0, StatusCode::OK);
    assert_eq!(call(&st, get("/ws")).await.0, StatusCode::UNAUTHORIZED);
    // The page (here the not-built notice) needs no token: it holds no secret.
    assert_eq!(call(&st, get("/")).await.0, StatusCode::OK);
}

#[test]
fn network_addresses_need_a_token() {
    let lan = "0.0.0.0:7878".parse().unwrap();
    assert!(check_listen(&lan, None).unwrap_err().contains("--token"));
    assert!(check_listen(&lan, Some("short")).is_err());
    assert!(check_listen(&lan, Some("0123456789abcdef")).is_ok());
    assert!(check_listen(&"127.0.0.1:1".parse().unwrap(), None).is_ok());
    assert!(check_listen(&"[::1]:1".parse().unwrap(), None).is_ok());
}

#[tokio::test]
async fn samples_and_the_opening_program_are_served() {
    let dir = tempfile::tempdir().unwrap();
    let st = state(dir.path(), None, 1 << 16);
    let (s, b) = call(&st, Request::get("/api/open").body(Body::empty()).unwrap()).await;
    assert_eq!(s, StatusCode::OK);
    let o = json(&b);
    assert_eq!(o["name"], "plate.nc");
    assert!(o["text"].as_str().unwrap().contains("G21"));
    let (s, b) = call(
        &st,
        Request::get("/api/samples/dome.png")
            .body(Body::empty())
            .unwrap(),
    )
    .await;
    assert_eq!(s, StatusCode::OK);
    assert_eq!(&b[1..4], b"PNG");
    let (s, _) = call(
        &st,
        Request::get("/api/samples/nope.nc")
            .body(Body::empty())
            .unwrap(),
    )
    .await;
    assert_eq!(s, StatusCode::NOT_FOUND);
}

/// Without `--web`, the page comes from the binary (built after `npm run build`), so a
/// release `oficina serve` works outside the checkout; before the page is built it says how.
#[tokio::test]
async fn the_binary_serves_the_page_it_carries() {
    let dir = tempfile::tempdir().unwrap();
    let st = state(dir.path(), None, 1 << 20);
    let get = |uri: &str| Request::get(uri).body(Body::empty()).unwrap();
    let (s, b) = call(&st, get("/")).await;
    let page = String::from_utf8_lossy(&b).to_string();
    assert_eq!(s, StatusCode::OK);
    if !oficina_server::page_built() {
        assert!(page.contains("npm run build"), "{page}");
        return;
    }
    assert!(page.contains("<script type=\"module\""), "{page}");
    // Every asset the page names is there, with its type.
    let asset = page
        .split("src=\"")
        .nth(1)
        .and_then(|r| r.split('"').next())
        .expect("the page names its script");
    let r = oficina_server::router(st.clone())
        .oneshot(get(asset))
        .await
        .unwrap();
    assert_eq!(r.status(), StatusCode::OK, "{asset}");
    assert_eq!(r.headers()["content-type"], "text/javascript", "{asset}");
    // An app path is the page; a missing asset is not.
    let (s, b) = call(&st, get("/some/view")).await;
    assert_eq!((s, b.len()), (StatusCode::OK, page.len()));
    let (s, _) = call(&st, get("/assets/missing.js")).await;
    assert_eq!(s, StatusCode::NOT_FOUND);
}
