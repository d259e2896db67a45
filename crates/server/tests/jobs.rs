//! The job endpoints (mill, sole, plot, carve, cancel) and their bad inputs, through the
//! router (no socket). Inputs are the repository's samples, uploaded into the job folder.

mod common;

use axum::body::Body;
use axum::http::{Request, StatusCode};
use common::{call, post, put, sample, state};
use serde_json::{json, Value};

#[tokio::test]
async fn mill_makes_a_checked_program_in_the_job_folder() {
    let dir = tempfile::tempdir().unwrap();
    let st = state(dir.path());
    put(&st, "plate.svg", sample("mill/plate.svg")).await;
    let (s, v) = post(&st, "/api/mill", json!({"file": "plate.svg", "params": {"op": "profile-out", "tool": "flat:3", "depth": 2, "tabs": 2}})).await;
    assert_eq!(s, StatusCode::OK, "{v}");
    assert_eq!(v["name"], "plate.profile-outside.ngc", "{v}");
    let text = v["text"].as_str().unwrap();
    assert!(text.contains("G1") && text.contains("M30"), "{text}");
    let report: Vec<&str> = v["report"]
        .as_array()
        .unwrap()
        .iter()
        .map(|l| l.as_str().unwrap())
        .collect();
    assert!(report[0].contains("gouge:    none"), "{report:?}");
    assert!(report.iter().any(|l| l.contains("(planner)")), "{report:?}");
    let saved = std::fs::read_to_string(dir.path().join("jobs/plate.profile-outside.ngc")).unwrap();
    assert_eq!(saved, text);
    assert!(v["preview_svg"].as_str().unwrap().starts_with("<svg"));
}

#[tokio::test]
async fn mill_reports_what_was_imported_closed_and_chained() {
    let dir = tempfile::tempdir().unwrap();
    let st = state(dir.path());
    // A 40 mm square as four separate paths, one drawn backwards, ends 5 µm apart.
    let svg = r#"<svg xmlns="http://www.w3.org/2000/svg" width="100mm" height="100mm" viewBox="0 0 100 100">
      <path d="M 10 10 L 50 10"/><path d="M 50 50 L 50.005 10"/>
      <path d="M 50 50 L 10 50"/><path d="M 10 50 L 10 10"/></svg>"#;
    put(&st, "square.svg", svg.as_bytes().to_vec()).await;
    let params = json!({"op": "profile-out", "tool": "flat:3", "depth": 2});
    let (s, v) = post(
        &st,
        "/api/mill",
        json!({"file": "square.svg", "params": params}),
    )
    .await;
    assert_eq!(s, StatusCode::OK, "{v}");
    let imported: Vec<&str> = v["imported"]
        .as_array()
        .unwrap()
        .iter()
        .map(|l| l.as_str().unwrap())
        .collect();
    assert!(
        imported[0].starts_with("4 paths read on 1 layer (svg)"),
        "{imported:?}"
    );
    assert!(
        imported[1].starts_with("1 closed loop: ")
            && imported[1].contains("1 chained from 4 pieces"),
        "{imported:?}"
    );
    // A tolerance below the gap leaves the square open, and says where.
    let params = json!({"op": "profile-on", "tool": "flat:3", "depth": 2, "join_tol": 0.001});
    let (s, v) = post(
        &st,
        "/api/mill",
        json!({"file": "square.svg", "params": params}),
    )
    .await;
    assert_eq!(s, StatusCode::OK, "{v}");
    let text = v["imported"].to_string();
    assert!(
        text.contains("open on layer svg: 1 path, largest gap 0.005 mm"),
        "{text}"
    );
}

#[tokio::test]
async fn mill_errors_name_the_field() {
    let dir = tempfile::tempdir().unwrap();
    let st = state(dir.path());
    put(&st, "plate.svg", sample("mill/plate.svg")).await;
    let cases = [
        (json!({"op": "pocket", "depth": 2, "safe_z": 1}), "safe_z"),
        (json!({"op": "pocket", "depth": 2, "feed": -5}), "feed"),
        (
            json!({"op": "pocket", "depth": 2, "tool": "spoon:3"}),
            "tool",
        ),
        (
            json!({"op": "pocket", "depth": 2, "post": "fanuc-9"}),
            "post",
        ),
        (
            json!({"op": "pocket", "depth": 2, "join_tol": 50}),
            "join_tol",
        ),
    ];
    for (params, field) in cases {
        let (s, v) = post(
            &st,
            "/api/mill",
            json!({"file": "plate.svg", "params": params}),
        )
        .await;
        assert_eq!(s, StatusCode::BAD_REQUEST, "{v}");
        assert_eq!(v["field"], field, "{v}");
        assert!(!v["error"].as_str().unwrap().is_empty());
    }
    // A parameter of the wrong kind, an unknown operation: refused by the form's reader.
    let (s, _) = post(
        &st,
        "/api/mill",
        json!({"file": "plate.svg", "params": {"op": "engrave"}}),
    )
    .await;
    assert!(s.is_client_error(), "{s}");
    // Files outside the job folder, or missing.
    for file in ["../plate.svg", "/etc/passwd", "missing.svg"] {
        let (s, v) = post(
            &st,
            "/api/mill",
            json!({"file": file, "params": {"depth": 1}}),
        )
        .await;
        assert!(s.is_client_error(), "{file}: {s} {v}");
    }
    // A broken drawing is named.
    let req = Request::put("/api/files/broken.svg")
        .body(Body::from("<svg><path d='M 0 0 L"))
        .unwrap();
    call(&st, req).await;
    let (s, v) = post(
        &st,
        "/api/mill",
        json!({"file": "broken.svg", "params": {"depth": 1}}),
    )
    .await;
    assert_eq!(s, StatusCode::BAD_REQUEST, "{v}");
    assert!(v["error"].as_str().unwrap().contains("broken.svg"), "{v}");
}

#[tokio::test]
async fn sole_makes_four_programs_and_refuses_bad_sizes() {
    let dir = tempfile::tempdir().unwrap();
    let st = state(dir.path());
    put(&st, "size34.csv", sample("sole/size34.csv")).await;
    let (s, v) = post(
        &st,
        "/api/sole",
        json!({"file": "size34.csv", "params": {"from_size": 34, "to_size": 37}}),
    )
    .await;
    assert_eq!(s, StatusCode::OK, "{v}");
    let programs = v["programs"].as_array().unwrap();
    assert_eq!(programs.len(), 4, "{v}");
    for p in programs {
        let name = p["name"].as_str().unwrap();
        assert!(dir.path().join("jobs").join(name).is_file(), "{name}");
    }
    assert!(v["summary"][0].as_str().unwrap().contains("α = "), "{v}");
    let (s, v) = post(
        &st,
        "/api/sole",
        json!({"file": "size34.csv", "params": {"from_size": 34, "to_size": 37, "shrink": 40}}),
    )
    .await;
    assert_eq!(s, StatusCode::BAD_REQUEST);
    assert_eq!(v["field"], "shrink", "{v}");
}

#[tokio::test]
async fn plot_writes_pen_moves_and_refuses_a_drawing_off_the_paper() {
    let dir = tempfile::tempdir().unwrap();
    let st = state(dir.path());
    put(&st, "design.svg", sample("plot/design.svg")).await;
    let (s, v) = post(
        &st,
        "/api/plot",
        json!({"file": "design.svg", "params": {}}),
    )
    .await;
    assert_eq!(s, StatusCode::OK, "{v}");
    assert_eq!(v["name"], "design.plot.ngc");
    assert!(!v["pens"].as_array().unwrap().is_empty(), "{v}");
    assert!(v["seconds"].as_f64().unwrap() > 0.0);
    let (s, v) = post(
        &st,
        "/api/plot",
        json!({"file": "design.svg", "params": {"paper": [5, 5]}}),
    )
    .await;
    assert_eq!(s, StatusCode::BAD_REQUEST, "{v}");
    assert!(v["error"].as_str().unwrap().contains("paper"), "{v}");
    let (s, v) = post(
        &st,
        "/api/plot",
        json!({"params": {"scale": 0}, "file": "design.svg"}),
    )
    .await;
    assert_eq!(s, StatusCode::BAD_REQUEST);
    assert_eq!(v["field"], "scale", "{v}");
    // The Plot form's layout: centred on a portrait A4 page inside 20 mm margins.
    let (s, v) = post(
        &st,
        "/api/plot",
        json!({"file": "design.svg", "params": {"layout": "a4", "margin": 20, "landscape": false, "no_fit": false}}),
    )
    .await;
    assert_eq!(s, StatusCode::OK, "{v}");
    let b: Vec<f64> = v["bounds"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    assert!(
        b[0] >= 20.0 - 1e-6 && b[1] >= 20.0 - 1e-6 && b[2] <= 190.0 + 1e-6 && b[3] <= 277.0 + 1e-6,
        "{b:?}"
    );
    assert!(
        (b[0] - 20.0).abs() < 1e-6 || (b[1] - 20.0).abs() < 1e-6,
        "fitted to a margin: {b:?}"
    );
    assert!(
        ((b[0] + b[2]) / 2.0 - 105.0).abs() < 1e-6 && ((b[1] + b[3]) / 2.0 - 148.5).abs() < 1e-6,
        "centred: {b:?}"
    );
    for (params, field) in [
        (json!({"layout": "a9"}), "layout"),
        (json!({"layout": "a4", "margin": 200}), "margin"),
    ] {
        let (s, v) = post(
            &st,
            "/api/plot",
            json!({"file": "design.svg", "params": params}),
        )
        .await;
        assert_eq!(s, StatusCode::BAD_REQUEST);
        assert_eq!(v["field"], field, "{v}");
    }
    let (s, _) = post(
        &st,
        "/api/plot",
        json!({"file": "design.svg", "profile": "no-such-plotter"}),
    )
    .await;
    assert_eq!(s, StatusCode::BAD_REQUEST);
    // The plot names the virtual plotter to run it on: the profile it was made for.
    let (s, v) = post(
        &st,
        "/api/plot",
        json!({"file": "design.svg", "profile": "pen-plotter"}),
    )
    .await;
    assert_eq!(s, StatusCode::OK, "{v}");
    assert_eq!(v["machine"], "virtual:pen-plotter");
    // A profile path outside the job folder is never read.
    let outside = dir.path().join("outside.toml");
    std::fs::write(&outside, "secret = 1\n").unwrap();
    for spec in [
        outside.display().to_string(),
        "../outside.toml".into(),
        "/etc/passwd".into(),
    ] {
        let (s, v) = post(
            &st,
            "/api/plot",
            json!({"file": "design.svg", "profile": spec}),
        )
        .await;
        assert_eq!(s, StatusCode::BAD_REQUEST, "{spec}: {v}");
        let msg = v["error"].as_str().unwrap();
        assert!(msg.contains("neither a bundled profile"), "{msg}");
        assert!(!msg.contains("secret") && !msg.contains("root:"), "{msg}");
    }
}

/// The stage and fraction of a live progress message.
fn progress_of(m: &str) -> Option<(String, f64)> {
    let v: Value = serde_json::from_str(m).ok()?;
    (v["type"] == "progress").then(|| {
        (
            v["stage"].as_str().unwrap_or_default().to_string(),
            v["fraction"].as_f64().unwrap_or(-1.0),
        )
    })
}

#[tokio::test]
async fn cancel_stops_a_long_carve_inside_its_pass_and_the_next_job_runs() {
    let dir = tempfile::tempdir().unwrap();
    let st = state(dir.path());
    let image = std::fs::read(format!(
        "{}/../../samples/relief/dome.png",
        env!("CARGO_MANIFEST_DIR")
    ))
    .unwrap();
    // Nothing to cancel: says so.
    let (s, v) = call(
        &st,
        Request::post("/api/cancel").body(Body::empty()).unwrap(),
    )
    .await;
    assert_eq!(s, StatusCode::OK);
    assert_eq!(v["cancelled"], false);
    // A large job: a wide carving with roughing, a fine step-over and fifty depth levels.
    let q = "name=dome.png&width=400&depth=5&tool=ball:1&rough_tool=flat:3&stepover=0.05&stepdown=0.1&feed=2000&plunge_feed=500&safe_z=5";
    let mut rx = st.live.subscribe();
    let carve = {
        let st = st.clone();
        let image = image.clone();
        tokio::spawn(async move {
            call(
                &st,
                Request::post(format!("/api/carve?{q}"))
                    .body(Body::from(image))
                    .unwrap(),
            )
            .await
        })
    };
    // Wait until a pass is partly done (progress within it), then cancel.
    let (stage, at_cancel) = loop {
        let m = rx.recv().await.unwrap();
        if let Some((stage, f)) = progress_of(&m) {
            if f > 0.0 && f < 1.0 {
                break (stage, f);
            }
        }
    };
    let (s, v) = call(
        &st,
        Request::post("/api/cancel").body(Body::empty()).unwrap(),
    )
    .await;
    assert_eq!(s, StatusCode::OK);
    assert_eq!(v["cancelled"], true);
    let (s, v) = carve.await.unwrap();
    assert_eq!(s, StatusCode::CONFLICT, "{v}");
    assert_eq!(v["cancelled"], true, "{v}");
    assert!(!dir.path().join("jobs/dome.nc").exists());
    // The answer came once the planner had stopped: nothing is being computed any more,
    // and the work done ends inside the pass that was cancelled (it never reached its
    // end, and no later pass began).
    let (s, v) = call(
        &st,
        Request::post("/api/cancel").body(Body::empty()).unwrap(),
    )
    .await;
    assert_eq!((s, v["cancelled"].as_bool()), (StatusCode::OK, Some(false)));
    let mut last = (stage.clone(), at_cancel);
    loop {
        match rx.try_recv() {
            Ok(m) => {
                if let Some(p) = progress_of(&m) {
                    last = p;
                }
            }
            Err(tokio::sync::broadcast::error::TryRecvError::Lagged(_)) => continue,
            Err(_) => break,
        }
    }
    assert_eq!(
        last.0, stage,
        "the job went on to another stage after the cancel"
    );
    assert!(
        last.1 < 1.0,
        "the cancelled pass ran to its end: {last:?} (cancelled at {at_cancel})"
    );
    // The next job is not refused as "another job is being computed".
    let q = "name=dome.png&width=20&depth=2&tool=ball:3&stepover=1&stepdown=5&feed=2000&plunge_feed=500&safe_z=5";
    let (s, v) = call(
        &st,
        Request::post(format!("/api/carve?{q}"))
            .body(Body::from(image))
            .unwrap(),
    )
    .await;
    assert_eq!(s, StatusCode::OK, "{v}");
    assert!(v["text"].as_str().unwrap().contains("G1"));
}
