//! What the server's test binaries share: a server on a scratch job folder, requests through
//! the router (no socket), and the live channel over a real socket.
// Each test binary compiles this module and uses part of it.
#![allow(dead_code)]

use axum::body::Body;
use axum::http::{Request, StatusCode};
use futures_util::{SinkExt, StreamExt};
use http_body_util::BodyExt;
use oficina_server::{router, AppState, Config};
use serde_json::Value;
use std::sync::Arc;
use std::time::Duration;
use tokio_tungstenite::tungstenite::Message;
use tower::ServiceExt;

/// A local server on a free port with its job folder in `dir`, the virtual machine and a
/// 1 MiB upload limit.
pub(crate) fn config(dir: &std::path::Path) -> Config {
    Config {
        addr: "127.0.0.1:0".parse().unwrap(),
        token: None,
        job_dir: dir.join("jobs"),
        web_dir: None,
        machine: "virtual".into(),
        upload_limit: 1 << 20,
        open: None,
        allowed_hosts: Vec::new(),
    }
}

/// The state of a server with [`config`].
pub(crate) fn state(dir: &std::path::Path) -> Arc<AppState> {
    AppState::new(config(dir)).unwrap()
}

/// The router's answer to `req`: status and body bytes.
pub(crate) async fn call_bytes(st: &Arc<AppState>, req: Request<Body>) -> (StatusCode, Vec<u8>) {
    let r = router(st.clone()).oneshot(req).await.unwrap();
    let status = r.status();
    let body = r.into_body().collect().await.unwrap().to_bytes().to_vec();
    (status, body)
}

/// The router's answer to `req`: status and body as JSON (a JSON string when it is not).
pub(crate) async fn call(st: &Arc<AppState>, req: Request<Body>) -> (StatusCode, Value) {
    let (status, body) = call_bytes(st, req).await;
    let v = serde_json::from_slice(&body)
        .unwrap_or_else(|_| Value::String(String::from_utf8_lossy(&body).into()));
    (status, v)
}

/// A POST of `body` as JSON.
pub(crate) fn post_json(uri: &str, body: Value) -> Request<Body> {
    Request::post(uri)
        .header("content-type", "application/json")
        .body(Body::from(body.to_string()))
        .unwrap()
}

/// Puts `bytes` into the job folder as `name`; it must be accepted.
pub(crate) async fn put(st: &Arc<AppState>, name: &str, bytes: Vec<u8>) {
    let req = Request::put(format!("/api/files/{name}"))
        .body(Body::from(bytes))
        .unwrap();
    let (s, v) = call(st, req).await;
    assert_eq!(s, StatusCode::OK, "{v}");
}

/// The repository's `samples/{path}`.
pub(crate) fn sample(path: &str) -> Vec<u8> {
    std::fs::read(format!(
        "{}/../../samples/{path}",
        env!("CARGO_MANIFEST_DIR")
    ))
    .unwrap()
}

/// Serves `config` on a socket; the address it listens on.
pub(crate) async fn serve(config: Config) -> std::net::SocketAddr {
    let (tx, rx) = tokio::sync::oneshot::channel();
    tokio::spawn(async move {
        oficina_server::serve(config, |a| {
            let _ = tx.send(a);
        })
        .await
        .unwrap();
    });
    rx.await.unwrap()
}

pub(crate) type Ws =
    tokio_tungstenite::WebSocketStream<tokio_tungstenite::MaybeTlsStream<tokio::net::TcpStream>>;

/// The live channel of the server at `addr`.
pub(crate) async fn connect(addr: std::net::SocketAddr) -> Ws {
    tokio_tungstenite::connect_async(format!("ws://{addr}/ws"))
        .await
        .unwrap()
        .0
}

/// How long [`until`] waits: a guard against a hang, not a measure.
const PATIENCE: Duration = Duration::from_secs(60);

/// The next message for which `want` is true (others are skipped), within [`PATIENCE`].
pub(crate) async fn until(ws: &mut Ws, want: impl Fn(&Value) -> bool) -> Value {
    let wait = async {
        while let Some(Ok(m)) = ws.next().await {
            if let Message::Text(t) = m {
                let v: Value = serde_json::from_str(&t).unwrap();
                if want(&v) {
                    return v;
                }
            }
        }
        panic!("the socket closed");
    };
    tokio::time::timeout(PATIENCE, wait)
        .await
        .unwrap_or_else(|_| panic!("no such message within {} s", PATIENCE.as_secs()))
}

/// Sends the command `v` and gives its answer (`ok` or `error`).
pub(crate) async fn send(ws: &mut Ws, v: Value) -> Value {
    ws.send(Message::Text(v.to_string().into())).await.unwrap();
    until(ws, |m| m["type"] == "ok" || m["type"] == "error").await
}

/// The router's answer to `body` POSTed as JSON to `uri`.
pub(crate) async fn post(st: &Arc<AppState>, uri: &str, body: Value) -> (StatusCode, Value) {
    call(st, post_json(uri, body)).await
}
