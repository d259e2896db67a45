//! The workbench server: HTTP and a WebSocket over `oficina-app`, and the page from `web/`.
//! No domain logic here: requests are parsed, the application layer is called, its data is
//! sent back as JSON (or, for previews, packed binary).
//!
//! ```
//! use axum::{body::Body, http::Request};
//! use oficina_server::{check_listen, router, AppState, Config};
//! use tower::ServiceExt; // oneshot: one request through the router, no socket
//!
//! // A network address needs a token; this computer alone does not.
//! assert!(check_listen(&"0.0.0.0:8080".parse().unwrap(), None).is_err());
//! assert!(check_listen(&"127.0.0.1:8080".parse().unwrap(), None).is_ok());
//!
//! let dir = tempfile::tempdir().unwrap();
//! let state = AppState::new(Config {
//!     addr: "127.0.0.1:0".parse().unwrap(), token: None, job_dir: dir.path().join("jobs"),
//!     web_dir: None, machine: "virtual".into(), upload_limit: 1 << 20, open: None,
//!     allowed_hosts: Vec::new(),
//! }).unwrap();
//! let program = "G21 G90\nG0 X0 Y0\nG1 X10 F600\nM2\n";
//! let check = Request::post("/api/check").body(Body::from(program)).unwrap();
//! let rt = tokio::runtime::Builder::new_current_thread().enable_all().build().unwrap();
//! let response = rt.block_on(router(state).oneshot(check)).unwrap();
//! assert_eq!(response.status(), 200);
//! let body = rt.block_on(http_body_util::BodyExt::collect(response.into_body())).unwrap();
//! let report: serde_json::Value = serde_json::from_slice(&body.to_bytes()).unwrap();
//! assert_eq!((report["errors"].as_u64(), report["feed_length"].as_f64()), (Some(0), Some(10.0)));
//! ```

mod api;
mod auth;
mod camjob;
mod carve_model;
mod design;
mod embroider;
mod files;
mod jobs;
mod macros;
mod page;
mod probing;
mod profiles;
mod samples;
mod simulate;
mod state;
mod stitches;
mod ws;

pub use state::{AppState, Config};

use axum::Router;
use std::net::SocketAddr;
use std::sync::Arc;

/// Every route: the API under /api, the live channel at /ws, the page everywhere else.
pub fn router(state: Arc<AppState>) -> Router {
    api::routes(state.clone())
        .merge(ws::routes(state.clone()))
        .fallback_service(api::page_service(&state))
        .layer(axum::middleware::from_fn_with_state(state, auth::guard))
}

/// True when this binary carries the built page (it was built after `npm run build`).
pub fn page_built() -> bool {
    page::built()
}

/// Refuse to listen beyond this computer without a token: anyone on the network could
/// otherwise move the machine.
pub fn check_listen(addr: &SocketAddr, token: Option<&str>) -> Result<(), String> {
    if addr.ip().is_loopback() {
        return Ok(());
    }
    match token {
        Some(t) if t.len() >= 16 => Ok(()),
        Some(_) => Err("--token: at least 16 characters on a network address".into()),
        None => Err(format!(
            "--listen {addr} reaches beyond this computer: give --token SECRET (16 characters or more); the page is then opened as http://{addr}/?token=SECRET"
        )),
    }
}

/// Bind, tell `ready` the address, and serve until the process ends.
pub async fn serve(
    config: Config,
    ready: impl FnOnce(SocketAddr),
) -> Result<(), Box<dyn std::error::Error>> {
    check_listen(&config.addr, config.token.as_deref())?;
    let listener = tokio::net::TcpListener::bind(config.addr)
        .await
        .map_err(|e| format!("cannot listen on {}: {e}", config.addr))?;
    let addr = listener.local_addr()?;
    // The port asked may have been 0: `Host:` is checked against the one bound.
    let config = Config { addr, ..config };
    let state = AppState::new(config)?;
    state::spawn_pump(state.clone());
    ready(addr);
    axum::serve(listener, router(state)).await?;
    Ok(())
}
