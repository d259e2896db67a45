//! The 3D model endpoints of the page (`/api/model/mesh`, `/api/model`) through the router:
//! a hand-written STL comes back as its own triangles, placed as `--size` places it; the
//! carving writes its program beside the model; bad models and settings are clear errors
//! naming what is wrong; the token guards both.

mod common;

use axum::http::StatusCode;
use base64::Engine;
use common::{call, config, post_json, put, state};
use oficina_server::AppState;
use serde_json::{json, Value};

/// A square pyramid: base 0..10 × 0..6 at Z 0, apex (5, 3, 4); six triangles.
const PYRAMID: &str = "solid pyramid
facet normal 0 0 -1
 outer loop
  vertex 0 0 0
  vertex 10 6 0
  vertex 10 0 0
 endloop
endfacet
facet normal 0 0 -1
 outer loop
  vertex 0 0 0
  vertex 0 6 0
  vertex 10 6 0
 endloop
endfacet
facet normal 0 -1 1
 outer loop
  vertex 0 0 0
  vertex 10 0 0
  vertex 5 3 4
 endloop
endfacet
facet normal 1 0 1
 outer loop
  vertex 10 0 0
  vertex 10 6 0
  vertex 5 3 4
 endloop
endfacet
facet normal 0 1 1
 outer loop
  vertex 10 6 0
  vertex 0 6 0
  vertex 5 3 4
 endloop
endfacet
facet normal -1 0 1
 outer loop
  vertex 0 6 0
  vertex 0 0 0
  vertex 5 3 4
 endloop
endfacet
endsolid pyramid
";

/// The vertices of the file, in its order.
fn file_vertices() -> Vec<f32> {
    PYRAMID
        .lines()
        .filter_map(|l| l.trim().strip_prefix("vertex "))
        .flat_map(|v| v.split_whitespace().map(|x| x.parse::<f32>().unwrap()))
        .collect()
}

fn decoded(v: &Value) -> Vec<f32> {
    let bytes = base64::engine::general_purpose::STANDARD
        .decode(v["positions"].as_str().unwrap())
        .unwrap();
    bytes
        .chunks(4)
        .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect()
}

/// The carve form as the page sends it (`oficina carve`'s defaults, a coarse grid).
fn form() -> Value {
    json!({
        "scale": 1, "rotate": 0, "tool": "ball:2", "scallop": 0.05, "rough_stepover": 0.8,
        "stepdown": 5, "allowance": 0.5, "direction": "x", "one_way": false, "no_rest": false,
        "feed": 2000, "plunge_feed": 500, "rpm": 18000, "safe_z": 5, "post": "grbl",
        "allow_m6": false, "tolerance": 0.002, "pixel_size": 0.2,
    })
}

#[tokio::test]
async fn a_model_comes_back_as_its_triangles_and_is_carved_beside_itself() {
    let dir = tempfile::tempdir().unwrap();
    let st = state(dir.path());
    put(&st, "pyramid.stl", PYRAMID.as_bytes().to_vec()).await;
    let (s, v) = call(
        &st,
        post_json(
            "/api/model/mesh",
            json!({"file": "pyramid.stl", "params": {"scale": 1, "rotate": 0}}),
        ),
    )
    .await;
    assert_eq!(s, StatusCode::OK, "{v}");
    assert_eq!(v["triangles"], 6);
    assert_eq!(v["bounds"], json!([[0.0, 0.0, 0.0], [10.0, 6.0, 4.0]]));
    assert_eq!(decoded(&v), file_vertices());
    // --size 20: the largest dimension (X, 10 mm) becomes 20 mm, the others in proportion.
    let (s, v) = call(
        &st,
        post_json(
            "/api/model/mesh",
            json!({"file": "pyramid.stl", "params": {"scale": 1, "rotate": 0, "size": 20}}),
        ),
    )
    .await;
    assert_eq!(s, StatusCode::OK, "{v}");
    assert_eq!(v["bounds"], json!([[0.0, 0.0, 0.0], [20.0, 12.0, 8.0]]));
    let (s, v) = call(
        &st,
        post_json(
            "/api/model",
            json!({"file": "pyramid.stl", "params": form()}),
        ),
    )
    .await;
    assert_eq!(s, StatusCode::OK, "{v}");
    assert_eq!(v["name"], "pyramid.nc");
    let text = v["text"].as_str().unwrap();
    assert_eq!(
        std::fs::read_to_string(dir.path().join("jobs/pyramid.nc")).unwrap(),
        text
    );
    assert!(text.contains("(model = pyramid.stl)"), "{text:.400}");
    // The ball never cuts into the pyramid (its faces are 39° to 53° from flat).
    assert!(
        v["report"]["max_gouge"].as_f64().unwrap() < 0.01,
        "{}",
        v["report"]
    );
    assert!(v["png"]
        .as_str()
        .unwrap()
        .starts_with("data:image/png;base64,"));
}

#[tokio::test]
async fn bad_models_and_settings_are_clear_errors() {
    let dir = tempfile::tempdir().unwrap();
    let st = state(dir.path());
    put(&st, "pyramid.stl", PYRAMID.as_bytes().to_vec()).await;
    put(&st, "flat.stl", b"solid f\nendsolid f\n".to_vec()).await;
    let with = |k: &str, v: Value| {
        let mut f = form();
        f[k] = v;
        f
    };
    for (file, params, says) in [
        ("../pyramid.stl", form(), "file name"),
        ("absent.stl", form(), "absent.stl"),
        ("flat.stl", form(), "flat.stl"),
        ("pyramid.stl", with("tool", json!("wrench:3")), "wrench"),
        ("pyramid.stl", with("scale", json!(0)), "--scale 0"),
        (
            "pyramid.stl",
            with("direction", json!("z")),
            "raster direction 'z'",
        ),
        ("pyramid.stl", with("post", json!("fanuc")), "fanuc"),
        (
            "pyramid.stl",
            with("strategy", json!("spiral")),
            "--strategy",
        ),
        (
            "pyramid.stl",
            with("roughing", json!("drill")),
            "--roughing",
        ),
    ] {
        let (s, v) = call(
            &st,
            post_json("/api/model", json!({"file": file, "params": params})),
        )
        .await;
        assert_eq!(s, StatusCode::BAD_REQUEST, "{file} {params}: {v}");
        assert!(v["error"].as_str().unwrap().contains(says), "{says}: {v}");
    }
}

#[tokio::test]
async fn the_token_guards_the_model_endpoints() {
    let dir = tempfile::tempdir().unwrap();
    let st = AppState::new(oficina_server::Config {
        token: Some("0123456789abcdef".into()),
        ..config(dir.path())
    })
    .unwrap();
    for uri in ["/api/model", "/api/model/mesh"] {
        let (s, _) = call(&st, post_json(uri, json!({"file": "a.stl", "params": {}}))).await;
        assert_eq!(s, StatusCode::UNAUTHORIZED, "{uri}");
    }
}
