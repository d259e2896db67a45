//! The live channel over a real socket: one page controls, others watch; a page that goes
//! away never stops the job; the page that comes back finds it where it is.

mod common;

use common::{connect, send, until};
use serde_json::{json, Value};
use std::time::Duration;

/// Serves a scratch job folder in `dir`; the address it listens on.
async fn server(dir: &std::path::Path) -> std::net::SocketAddr {
    common::serve(common::config(dir)).await
}

fn state_is(s: &'static str) -> impl Fn(&Value) -> bool {
    move |m| m["type"] == "status" && m["status"]["state"] == s
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn one_page_controls_and_a_dropped_page_never_stops_the_job() {
    let dir = tempfile::tempdir().unwrap();
    let addr = server(dir.path()).await;
    let mut a = connect(addr).await;
    let hello = until(&mut a, |m| m["type"] == "hello").await;
    assert_eq!(hello["controller"], true);
    let mut b = connect(addr).await;
    let hello_b = until(&mut b, |m| m["type"] == "hello").await;
    assert_eq!(hello_b["controller"], false);

    // The watcher may not move the machine (nor type a line)…
    for cmd in [
        json!({"cmd": "jog", "delta": [1.0, 0.0, 0.0], "feed": 100.0}),
        json!({"cmd": "mdi", "line": "G0 X1"}),
    ] {
        let r = send(&mut b, cmd).await;
        assert_eq!(r["type"], "error");
        assert!(r["message"].as_str().unwrap().contains("controls"), "{r}");
    }
    // …but it may hold, stop and reset (here nothing runs: the machine says so).
    let r = send(&mut b, json!({"cmd": "hold"})).await;
    assert!(!r.to_string().contains("controls"), "{r}");
    let r = send(&mut b, json!({"cmd": "soft_reset"})).await;
    assert_eq!(r["type"], "ok", "{r}");
    // Bad commands are refused with the reason.
    let r = send(&mut a, json!({"cmd": "fly"})).await;
    assert!(
        r["message"].as_str().unwrap().contains("bad command"),
        "{r}"
    );
    let r = send(&mut a, json!({"cmd": "start", "file": "../x.nc"})).await;
    assert_eq!(r["type"], "error", "{r}");
    let r = send(&mut a, json!({"cmd": "feed_override", "value": 9.0})).await;
    assert_eq!(r["type"], "error", "{r}");
    // A machine that cannot be opened leaves the connected one in place.
    let r = send(&mut a, json!({"cmd": "connect", "uri": "no-such-profile"})).await;
    assert!(
        r["message"].as_str().unwrap().contains("no-such-profile"),
        "{r}"
    );

    // The controller starts the bundled sample (81 s of machine time) at 5x.
    let r = send(
        &mut a,
        json!({"cmd": "start", "file": "plate.nc", "speed": 5.0}),
    )
    .await;
    assert_eq!(r["type"], "ok", "{r}");
    until(&mut b, state_is("run")).await;
    // The controlling page goes away mid-job.
    drop(a);
    let c = until(&mut b, |m| m["type"] == "control").await;
    assert_eq!(c["controller"], Value::Null);
    let s = until(&mut b, state_is("run")).await;
    let line_then = s["status"]["line"].as_u64().unwrap();

    // A page that comes back sees the job where it is, and its text.
    let mut a2 = connect(addr).await;
    let hello = until(&mut a2, |m| m["type"] == "hello").await;
    assert_eq!(
        hello["controller"], true,
        "control was free: the new page has it"
    );
    let s = until(&mut a2, state_is("run")).await;
    assert!(s["status"]["line"].as_u64().unwrap() >= line_then);
    assert_eq!(s["status"]["job"]["name"], "plate.nc");
    let job: Value = serde_json::from_str(
        &tokio::task::spawn_blocking(move || http_get(addr, "/api/job"))
            .await
            .unwrap(),
    )
    .unwrap();
    assert_eq!(job["name"], "plate.nc");

    // Hold, then resume, then the job ends complete.
    assert_eq!(send(&mut a2, json!({"cmd": "hold"})).await["type"], "ok");
    let held = until(&mut a2, state_is("hold")).await;
    let t = held["status"]["elapsed"].as_f64().unwrap();
    tokio::time::sleep(Duration::from_millis(300)).await;
    let still = until(&mut a2, state_is("hold")).await;
    assert_eq!(
        still["status"]["elapsed"].as_f64().unwrap(),
        t,
        "held means still"
    );
    assert_eq!(send(&mut a2, json!({"cmd": "resume"})).await["type"], "ok");
    let end = until(&mut a2, |m| {
        m["type"] == "event" && m["event"]["type"] == "job_end"
    })
    .await;
    assert_eq!(end["event"]["completed"], true, "{end}");
    let s = until(&mut a2, state_is("idle")).await;
    assert_eq!(s["status"]["job"]["completed"], true);
}

/// A plain HTTP GET (the test needs no HTTP client crate for one request).
fn http_get(addr: std::net::SocketAddr, path: &str) -> String {
    use std::io::{Read, Write};
    let mut s = std::net::TcpStream::connect(addr).unwrap();
    write!(
        s,
        "GET {path} HTTP/1.1\r\nHost: {addr}\r\nConnection: close\r\n\r\n"
    )
    .unwrap();
    let mut out = String::new();
    s.read_to_string(&mut out).unwrap();
    let body = out.split_once("\r\n\r\n").unwrap().1;
    // Chunked or not, the JSON object is the part between the outer braces.
    let (a, b) = (body.find('{').unwrap(), body.rfind('}').unwrap());
    body[a..=b].to_string()
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_page_connects_only_to_bundled_or_job_folder_profiles() {
    let dir = tempfile::tempdir().unwrap();
    let addr = server(dir.path()).await;
    let mut a = connect(addr).await;
    until(&mut a, |m| m["type"] == "hello").await;
    // A file elsewhere on this computer is never read as a profile.
    let outside = dir.path().join("elsewhere.toml");
    std::fs::write(&outside, "secret = 1\n").unwrap();
    for uri in [
        format!("virtual:{}", outside.display()),
        "virtual:../elsewhere.toml".to_string(),
        "virtual:/etc/passwd".to_string(),
        "virtualpen-plotter".to_string(),
    ] {
        let r = send(&mut a, json!({"cmd": "connect", "uri": uri})).await;
        assert_eq!(r["type"], "error", "{uri}: {r}");
        let msg = r["message"].as_str().unwrap();
        assert!(!msg.contains("secret") && !msg.contains("root:"), "{msg}");
    }
    // A bundled plotter, and a profile file saved in the job folder, connect.
    let r = send(
        &mut a,
        json!({"cmd": "connect", "uri": "virtual:pen-plotter"}),
    )
    .await;
    assert_eq!(r["type"], "ok", "{r}");
    let text = oficina_app::profile::BUNDLED
        .iter()
        .find(|(n, _)| *n == "grbl-router")
        .unwrap()
        .1;
    std::fs::write(dir.path().join("jobs/mine.toml"), text).unwrap();
    let r = send(
        &mut a,
        json!({"cmd": "connect", "uri": "virtual:mine.toml"}),
    )
    .await;
    assert_eq!(r["type"], "ok", "{r}");
}
