//! The CAM job endpoints of the page (`/api/mill-job`, `/api/mill-job/shapes`,
//! `/api/mill-job/stock`) through the router: the shapes the page draws carry the import
//! report's ids; a job written with those ids gives the program of the hand-written job that
//! selects by colour and size; the stock after each operation is the job's program up to the
//! next operation, removing more at each; bad names and keys are clear errors; the token
//! guards them as every /api route.

mod common;

use axum::http::StatusCode;
use common::{call, config, post_json, put, state};
use oficina_app::{mill_job, mill_job_upto, Feedback, JobOptions};
use oficina_server::AppState;
use serde_json::json;
use std::sync::atomic::AtomicBool;

fn jobs_dir() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/data/jobs")
}

/// A server on `dir` with tests/data/jobs/nested-plate.svg in its job folder.
async fn with_plate(dir: &std::path::Path) -> std::sync::Arc<AppState> {
    let st = state(dir);
    put(
        &st,
        "nested-plate.svg",
        std::fs::read(jobs_dir().join("nested-plate.svg")).unwrap(),
    )
    .await;
    st
}

/// The page's job for tests/data/jobs/nested-plate.toml: the same ops on shape ids.
fn page_job(holes: &[u64], red: &[u64]) -> String {
    let ids = |v: &[u64]| {
        v.iter()
            .map(|i| i.to_string())
            .collect::<Vec<_>>()
            .join(", ")
    };
    format!(
        r#"drawing = "nested-plate.svg"
[stock]
thickness = 5
size = [90, 60]
corner = [-5, -5]

[[op]]
name = "small holes"
kind = "profile-in"
select = {{ ids = [{}] }}
tool = "flat:3"
depth = 5.3
stepdown = 1.5
feed = 900
rpm = 18000

[[op]]
name = "deburr"
kind = "chamfer"
select = {{ ids = [{}] }}
tool = "v:6:90"
width = 0.6
feed = 600
rpm = 16000

[[op]]
name = "cut-out"
kind = "profile-out"
select = {{}}
tool = "flat:3"
depth = 5.3
stepdown = 1.5
feed = 900
rpm = 18000
tabs = {{ count = 3, width = 4, height = 1.2 }}
"#,
        ids(holes),
        ids(red)
    )
}

/// The program's lines but those naming the job file and the drawing's path.
fn body(p: &str) -> Vec<&str> {
    p.lines()
        .filter(|l| !l.starts_with("(job = ") && !l.starts_with("(drawing = "))
        .collect()
}

#[tokio::test]
async fn a_job_on_the_shapes_ids_gives_the_hand_written_jobs_program() {
    let dir = tempfile::tempdir().unwrap();
    let st = with_plate(dir.path()).await;
    let head = "drawing = \"nested-plate.svg\"\n[stock]\nthickness = 5\n";
    let (s, v) = call(
        &st,
        post_json(
            "/api/mill-job/shapes",
            json!({"name": "plate.toml", "toml": head}),
        ),
    )
    .await;
    assert_eq!(s, StatusCode::OK, "{v}");
    let shapes = v["shapes"].as_array().unwrap();
    // The hand-written job, by the library's own call: its report lists the same shapes.
    let hand = mill_job(
        &jobs_dir().join("nested-plate.toml"),
        &JobOptions::default(),
        &Err("no profile".into()),
        Feedback {
            progress: &|_, _| {},
            cancel: &AtomicBool::new(false),
        },
    )
    .unwrap();
    let lines: Vec<&str> = shapes
        .iter()
        .map(|s| s["describe"].as_str().unwrap())
        .collect();
    assert_eq!(lines, hand.shapes);
    for (k, s) in shapes.iter().enumerate() {
        assert_eq!(s["id"], k + 1);
        assert!(s["points"].as_array().unwrap().len() >= 2, "{s}");
    }
    // The page picks by id what the hand-written job picks by colour and size.
    let red: Vec<u64> = shapes
        .iter()
        .filter(|s| s["color"] == "#ff0000")
        .map(|s| s["id"].as_u64().unwrap())
        .collect();
    let holes: Vec<u64> = shapes
        .iter()
        .filter(|s| s["color"] == "#ff0000" && s["circle"].as_f64().is_some_and(|d| d < 10.0))
        .map(|s| s["id"].as_u64().unwrap())
        .collect();
    assert!(
        !holes.is_empty() && red.len() >= holes.len(),
        "{red:?} {holes:?}"
    );
    let (s, v) = call(
        &st,
        post_json(
            "/api/mill-job",
            json!({"name": "plate.job.toml", "toml": page_job(&holes, &red)}),
        ),
    )
    .await;
    assert_eq!(s, StatusCode::OK, "{v}");
    assert_eq!(v["name"], "plate.ngc");
    let text = v["text"].as_str().unwrap();
    assert_eq!(body(text), body(&hand.programs[0].judged.program));
    assert_eq!(
        std::fs::read_to_string(dir.path().join("jobs/plate.ngc")).unwrap(),
        text
    );
    assert_eq!(
        std::fs::read_to_string(dir.path().join("jobs/plate.job.toml")).unwrap(),
        page_job(&holes, &red)
    );
    assert_eq!(v["gouged"], false);
    assert_eq!(v["tool_loads"], hand.tool_loads);
    let ops = v["ops"].as_array().unwrap();
    assert_eq!(ops.len(), 3);
    for o in ops {
        // Each toolpath lies within the drawing's cuts (the stock is 90 × 60 from -5, -5).
        for p in o["path"]
            .as_array()
            .unwrap()
            .iter()
            .flat_map(|l| l.as_array().unwrap())
        {
            let (x, y) = (p[0].as_f64().unwrap(), p[1].as_f64().unwrap());
            assert!(
                (-6.0..86.0).contains(&x) && (-6.0..56.0).contains(&y),
                "{o:?}"
            );
        }
    }
}

/// A program's lines but its comments (which name the operations written).
fn cutting<'a>(lines: &[&'a str]) -> Vec<&'a str> {
    lines
        .iter()
        .copied()
        .filter(|l| !l.starts_with('('))
        .collect()
}

#[tokio::test]
async fn the_stock_after_each_operation_is_the_program_up_to_it() {
    let dir = tempfile::tempdir().unwrap();
    let st = with_plate(dir.path()).await;
    let toml = std::fs::read_to_string(jobs_dir().join("nested-plate.toml")).unwrap();
    let job = json!({"name": "plate.job.toml", "toml": toml});
    let (s, whole) = call(&st, post_json("/api/mill-job", job.clone())).await;
    assert_eq!(s, StatusCode::OK, "{whole}");
    let full = whole["text"].as_str().unwrap();
    let n = whole["ops"].as_array().unwrap().len();
    // Where each operation starts in the whole program (its comment line).
    let lines: Vec<&str> = full.lines().collect();
    let starts: Vec<usize> = (0..lines.len())
        .filter(|&i| lines[i].starts_with("(operation: "))
        .collect();
    assert_eq!(starts.len(), n);
    let mut removed = 0.0;
    for upto in 1..=n {
        let mut req = job.clone();
        req["upto"] = json!(upto);
        req["resolution"] = json!(0.25);
        let (s, v) = call(&st, post_json("/api/mill-job/stock", req)).await;
        assert_eq!(s, StatusCode::OK, "{v}");
        assert_eq!(v["ops"].as_array().unwrap().len(), upto);
        assert_eq!(v["gouged"], false, "{v}");
        let r = v["report"]["removed_mm3"].as_f64().unwrap();
        assert!(
            r > removed,
            "after {upto}: {r} mm³, not more than {removed}"
        );
        removed = r;
        assert!(v["png"]
            .as_str()
            .unwrap()
            .starts_with("data:image/png;base64,"));
        // The job stopped there (what the stock is simulated on) is the whole program cut
        // before the next operation, then the end (retract, M5, M30).
        let stopped = mill_job_upto(
            &dir.path().join("jobs/plate.job.toml"),
            &JobOptions::default(),
            &Err("no profile".into()),
            Some(upto),
            Feedback::none(),
        )
        .unwrap();
        let stopped = &stopped.programs[0].judged.program;
        let end = starts.get(upto).copied().unwrap_or(lines.len());
        let want = cutting(&lines[..end]);
        let got = cutting(&stopped.lines().collect::<Vec<_>>());
        assert_eq!(&got[..want.len()], &want[..], "after {upto}");
        let tail = &got[want.len()..];
        assert!(
            tail.len() <= 4
                && !tail
                    .iter()
                    .any(|l| l.starts_with("G1") || l.starts_with("G2") || l.starts_with("G3")),
            "after {upto}: the end is {tail:?}"
        );
    }
    // The job's stock as its file gives it, for the page.
    assert_eq!(whole["stock"]["size"], json!([90.0, 60.0]), "{whole}");
}

#[tokio::test]
async fn bad_jobs_are_clear_errors() {
    let dir = tempfile::tempdir().unwrap();
    let st = with_plate(dir.path()).await;
    for (uri, name, toml, says) in [
        ("/api/mill-job", "plate.nc", "drawing = \"nested-plate.svg\"\n[stock]\nthickness = 5\n", "ends in .toml"),
        ("/api/mill-job/shapes", "../plate.toml", "drawing = \"nested-plate.svg\"\n[stock]\nthickness = 5\n", "file name"),
        ("/api/mill-job/shapes", "plate.toml", "drawing = \"nested-plate.svg\"\n[stock]\nthikness = 5\n", "thikness"),
        ("/api/mill-job/shapes", "plate.toml", "drawing = \"absent.svg\"\n[stock]\nthickness = 5\n", "absent.svg"),
        ("/api/mill-job", "plate.toml", "drawing = \"nested-plate.svg\"\n[stock]\nthickness = 5\n[[op]]\nkind = \"pocket\"\nselect = { ids = [99] }\ntool = \"flat:3\"\ndepth = 1\n", "99"),
    ] {
        let (s, v) = call(&st, post_json(uri, json!({"name": name, "toml": toml}))).await;
        assert_eq!(s, StatusCode::BAD_REQUEST, "{uri} {name}: {v}");
        assert!(v["error"].as_str().unwrap().contains(says), "{says}: {v}");
    }
    let (s, v) = call(&st, post_json("/api/mill-job", json!({"name": "plate.toml", "toml": "drawing = \"nested-plate.svg\"\n[stock]\nthickness = 5\n"}))).await;
    assert_eq!(s, StatusCode::BAD_REQUEST, "{v}");
    assert!(v["error"].as_str().unwrap().contains("no [[op]]"), "{v}");
    // The stock after an operation the job does not have.
    let toml = std::fs::read_to_string(jobs_dir().join("nested-plate.toml")).unwrap();
    for upto in [0, 4] {
        let (s, v) = call(
            &st,
            post_json(
                "/api/mill-job/stock",
                json!({"name": "plate.toml", "toml": toml, "upto": upto}),
            ),
        )
        .await;
        assert_eq!(s, StatusCode::BAD_REQUEST, "{v}");
        assert!(
            v["error"].as_str().unwrap().contains(&format!(
                "up to operation {upto}: the job has operations 1 to 3"
            )),
            "{v}"
        );
    }
}

#[tokio::test]
async fn the_token_guards_the_job_endpoints() {
    let dir = tempfile::tempdir().unwrap();
    let st = AppState::new(oficina_server::Config {
        token: Some("0123456789abcdef".into()),
        ..config(dir.path())
    })
    .unwrap();
    for uri in [
        "/api/mill-job",
        "/api/mill-job/shapes",
        "/api/mill-job/stock",
    ] {
        let (s, _) = call(&st, post_json(uri, json!({"name": "a.toml", "toml": ""}))).await;
        assert_eq!(s, StatusCode::UNAUTHORIZED, "{uri}");
    }
}
