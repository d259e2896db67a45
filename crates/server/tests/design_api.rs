//! The design editor's endpoints (`/api/design/*`) through the router: the offset of a
//! filleted plate has the hand-derived corners, the DXF export names the bulge, a fit of an
//! ellipse's points encloses its area, and a bad design or request is a 400 naming the place.

mod common;

use axum::http::StatusCode;
use common::{post, state};
use serde_json::json;

fn plate() -> serde_json::Value {
    json!({"format": "oficina-design", "version": 1,
      "layers": [{"name": "0", "color": "#000000"}],
      "entities": [{"id": 1, "layer": "0", "type": "polyline", "closed": true,
        "vertices": [[0, 0], [60, 0], [60, 35, 0.41421356237309503], [55, 40], [0, 40]]}]})
}

#[tokio::test]
async fn offset_export_and_fit() {
    let dir = tempfile::tempdir().unwrap();
    let st = state(dir.path());
    let (s, v) = post(
        &st,
        "/api/design/offset",
        json!({"design": plate(), "ids": [1], "distance": -3}),
    )
    .await;
    assert_eq!(s, StatusCode::OK, "{v}");
    let e = &v["entities"][0];
    assert_eq!(
        (e["id"].as_u64(), e["type"].as_str()),
        (Some(2), Some("polyline"))
    );
    // 3 mm inside the plate: the corners (3, 3), (57, 3), (3, 37) among the vertices.
    let vs = e["vertices"].as_array().unwrap();
    for want in [[3.0, 3.0], [57.0, 3.0], [3.0, 37.0]] {
        assert!(
            vs.iter()
                .any(|p| (p[0].as_f64().unwrap() - want[0]).abs() < 1e-9
                    && (p[1].as_f64().unwrap() - want[1]).abs() < 1e-9),
            "{want:?} in {vs:?}"
        );
    }
    let (s, v) = post(
        &st,
        "/api/design/export",
        json!({"design": plate(), "format": "dxf"}),
    )
    .await;
    assert_eq!(s, StatusCode::OK, "{v}");
    assert!(v["text"]
        .as_str()
        .unwrap()
        .contains("42\n0.41421356237309503\n"));
    // 16 points of the ellipse 30 × 20: the biarc fit encloses πab within 1 %.
    let pts: Vec<[f64; 2]> = (0..16)
        .map(|k| {
            let t = std::f64::consts::TAU * k as f64 / 16.0;
            [30.0 * t.cos(), 20.0 * t.sin()]
        })
        .collect();
    let (s, v) = post(
        &st,
        "/api/design/fit",
        json!({"points": pts, "method": "biarc", "tol": 0.1}),
    )
    .await;
    assert_eq!(s, StatusCode::OK, "{v}");
    assert!(v["max_deviation"].as_f64().unwrap() <= 0.1, "{v}");
    let shape: oficina_app::design::Shape = serde_json::from_value(v["shape"].clone()).unwrap();
    let path = oficina_app::design::entity_paths(&shape).remove(0);
    let want = std::f64::consts::PI * 600.0;
    assert!(
        (path.area().abs() - want).abs() < 0.01 * want,
        "{}",
        path.area()
    );
}

#[tokio::test]
async fn bad_requests_name_the_place() {
    let dir = tempfile::tempdir().unwrap();
    let st = state(dir.path());
    let mut bad = plate();
    bad["entities"][0]["layer"] = json!("nowhere");
    let (s, v) = post(
        &st,
        "/api/design/offset",
        json!({"design": bad, "ids": [1], "distance": 1}),
    )
    .await;
    assert_eq!(s, StatusCode::BAD_REQUEST);
    assert!(
        v["error"].as_str().unwrap().contains("entities[0] (id 1)"),
        "{v}"
    );
    let (s, v) = post(
        &st,
        "/api/design/export",
        json!({"design": plate(), "format": "pdf"}),
    )
    .await;
    assert_eq!(s, StatusCode::BAD_REQUEST);
    assert!(
        v["error"]
            .as_str()
            .unwrap()
            .contains("'pdf' is not svg, dxf or seed001"),
        "{v}"
    );
    let (s, v) = post(
        &st,
        "/api/design/fit",
        json!({"points": [[0, 0], [1, 1]], "method": "spirograph", "tol": 0.1}),
    )
    .await;
    assert_eq!(s, StatusCode::BAD_REQUEST);
    assert!(v["error"].as_str().unwrap().contains("biarc"), "{v}");
}
