//! `POST /api/simulate`: the page's program on a box of stock, and its bad inputs.

mod common;

use axum::body::Body;
use axum::http::{Request, StatusCode};
use common::call_bytes as call;
use oficina_server::{AppState, Config};

fn post(uri: &str, body: &'static str) -> Request<Body> {
    Request::post(uri).body(Body::from(body)).unwrap()
}

/// A 10 × 10 mm square traced 1 mm deep by a 4 mm flat: a ring 4 mm wide round a 6 mm
/// island and inside a 14 mm square with quarter-disc corners.
const SQUARE: &str = "G21 G90\nG0 X0 Y0 Z5\nG1 Z-1 F100\nG1 X10 F600\nY10\nX0\nY0\nG0 Z5\nM2\n";

#[tokio::test]
async fn the_stock_comes_back_with_its_report_and_png() {
    let dir = tempfile::tempdir().unwrap();
    let st = AppState::new(Config {
        upload_limit: 1 << 20,
        ..common::config(dir.path())
    })
    .unwrap();
    let (s, b) = call(
        &st,
        post(
            "/api/simulate?stock=auto&tool=flat:4&resolution=0.05",
            SQUARE,
        ),
    )
    .await;
    assert_eq!(s, StatusCode::OK, "{}", String::from_utf8_lossy(&b));
    let r: serde_json::Value = serde_json::from_slice(&b).unwrap();
    // Geometry: (14² − 6²) minus the four corners' (1 − π/4)·2², times 1 mm.
    let volume = 14.0f64 * 14.0 - 36.0 - 4.0 * (1.0 - std::f64::consts::PI / 4.0) * 4.0;
    let got = r["report"]["removed_mm3"].as_f64().unwrap();
    assert!((got - volume).abs() < 0.03 * volume, "{got} vs {volume}");
    assert!(r["png"]
        .as_str()
        .unwrap()
        .starts_with("data:image/png;base64,iVBORw0KGgo"));

    let (s, b) = call(&st, post("/api/simulate?stock=0x10x10", SQUARE)).await;
    assert_eq!(s, StatusCode::BAD_REQUEST);
    assert!(String::from_utf8_lossy(&b).contains("stock width 0"));
    let (s, _) = call(&st, post("/api/simulate?tool=spoon:3", SQUARE)).await;
    assert_eq!(s, StatusCode::BAD_REQUEST);
}
