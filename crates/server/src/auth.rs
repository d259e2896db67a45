//! The token that guards the API when the server listens beyond loopback: as a bearer
//! header, or `?token=` (a WebSocket from a browser cannot set headers).

use crate::AppState;
use axum::extract::{Request, State};
use axum::http::StatusCode;
use axum::middleware::Next;
use axum::response::{IntoResponse, Response};
use std::sync::Arc;

pub(crate) async fn require_token(
    State(state): State<Arc<AppState>>,
    req: Request,
    next: Next,
) -> Response {
    let Some(token) = state.config.token.as_deref() else {
        return next.run(req).await;
    };
    let header_ok = req
        .headers()
        .get(axum::http::header::AUTHORIZATION)
        .and_then(|v| v.to_str().ok())
        .and_then(|v| v.strip_prefix("Bearer "))
        .is_some_and(|t| same(t, token));
    let query_ok = req.uri().query().is_some_and(|q| {
        q.split('&')
            .filter_map(|kv| kv.strip_prefix("token="))
            .any(|t| same(t, token))
    });
    if header_ok || query_ok {
        next.run(req).await
    } else {
        (
            StatusCode::UNAUTHORIZED,
            "this server needs its token: open the page as /?token=SECRET",
        )
            .into_response()
    }
}

/// Compare without stopping at the first difference (no timing hint about the token).
fn same(a: &str, b: &str) -> bool {
    a.len() == b.len()
        && a.bytes()
            .zip(b.bytes())
            .fold(0u8, |acc, (x, y)| acc | (x ^ y))
            == 0
}

/// Every request, the page's files included, passes here first. A server that moves a
/// machine is reachable by every page the user's browser opens, so it answers only its own:
/// - `Host:` must name this server: the address it listens on (an IP literal cannot be
///   rebound), `localhost` when it listens on loopback, or a name given with
///   `--allow-host`. A page of `evil.example` whose name an attacker re-points at 127.0.0.1
///   (DNS rebinding) sends `Host: evil.example:PORT` and is refused before any route.
/// - `Origin:`, which browsers send with every WebSocket handshake and every cross-origin or
///   state-changing request, must be this server's own (`null`, from a sandboxed frame or a
///   file, is refused). Requests without it come from programs, not pages: they pass, and
///   the token still guards a network address.
pub(crate) async fn guard(
    State(state): State<Arc<AppState>>,
    req: Request,
    next: Next,
) -> Response {
    match check_request(&state.config, req.headers()) {
        Ok(()) => next.run(req).await,
        Err(why) => (StatusCode::FORBIDDEN, why).into_response(),
    }
}

/// Why `headers` do not come from this server's own page, if they don't.
fn check_request(config: &crate::Config, headers: &axum::http::HeaderMap) -> Result<(), String> {
    let text = |name: axum::http::HeaderName| {
        headers
            .get(name)
            .map(|v| {
                v.to_str()
                    .map_err(|_| "a header that is not text".to_string())
            })
            .transpose()
    };
    let host = text(axum::http::header::HOST)?;
    if let Some(host) = host {
        if !host_allowed(config, host) {
            return Err(format!(
                "this server answers to {} only, not to Host: {host} (give another name with --allow-host)",
                config.addr
            ));
        }
    }
    if let Some(origin) = text(axum::http::header::ORIGIN)? {
        let own = host.is_some_and(|h| {
            origin.eq_ignore_ascii_case(&format!("http://{h}"))
                || origin.eq_ignore_ascii_case(&format!("https://{h}"))
        });
        if !own {
            return Err(format!(
                "this server answers its own page only, not a page of {origin}"
            ));
        }
    }
    Ok(())
}

/// `host` (a `Host:` value, `name[:port]`) names this server. Without a port it means the
/// scheme's default, 80.
pub(crate) fn host_allowed(config: &crate::Config, host: &str) -> bool {
    let (name, port) = split_host(host);
    let port = match port {
        Some(p) => p.parse::<u16>().ok(),
        None => Some(80),
    };
    if port != Some(config.addr.port()) {
        return config
            .allowed_hosts
            .iter()
            .any(|a| a.eq_ignore_ascii_case(host));
    }
    let listen = config.addr.ip();
    match name
        .trim_start_matches('[')
        .trim_end_matches(']')
        .parse::<std::net::IpAddr>()
    {
        Ok(ip) => {
            ip == listen || listen.is_unspecified() || (listen.is_loopback() && ip.is_loopback())
        }
        Err(_) => {
            // `localhost` always resolves to this computer in browsers: never rebound.
            ((listen.is_loopback() || listen.is_unspecified())
                && name.eq_ignore_ascii_case("localhost"))
                || config
                    .allowed_hosts
                    .iter()
                    .any(|a| a.eq_ignore_ascii_case(name) || a.eq_ignore_ascii_case(host))
        }
    }
}

/// `name[:port]`, `[v6][:port]` → (name, port).
fn split_host(host: &str) -> (&str, Option<&str>) {
    if let Some(rest) = host.strip_prefix('[') {
        return match rest.split_once(']') {
            Some((ip, tail)) => (&host[..ip.len() + 2], tail.strip_prefix(':')),
            None => (host, None),
        };
    }
    match host.rsplit_once(':') {
        Some((name, port)) => (name, Some(port)),
        None => (host, None),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use axum::http::{HeaderMap, HeaderValue};

    fn config(addr: &str, allow: &[&str]) -> crate::Config {
        crate::Config {
            addr: addr.parse().unwrap(),
            token: None,
            job_dir: "jobs".into(),
            web_dir: None,
            machine: "virtual".into(),
            upload_limit: 1,
            open: None,
            allowed_hosts: allow.iter().map(|s| s.to_string()).collect(),
        }
    }

    fn headers(host: Option<&str>, origin: Option<&str>) -> HeaderMap {
        let mut h = HeaderMap::new();
        if let Some(v) = host {
            h.insert("host", HeaderValue::from_str(v).unwrap());
        }
        if let Some(v) = origin {
            h.insert("origin", HeaderValue::from_str(v).unwrap());
        }
        h
    }

    #[test]
    fn only_this_servers_names_are_answered() {
        let c = config("127.0.0.1:7878", &["cnc.lan"]);
        for ok in [
            "127.0.0.1:7878",
            "localhost:7878",
            "LOCALHOST:7878",
            "[::1]:7878",
            "cnc.lan:7878",
        ] {
            assert!(host_allowed(&c, ok), "{ok}");
        }
        for bad in [
            "evil.example:7878",
            "127.0.0.1:7879",
            "localhost",
            "127.0.0.1",
            "192.168.1.5:7878",
            "localhost.evil.example:7878",
            "[::1]",
        ] {
            assert!(!host_allowed(&c, bad), "{bad}");
        }
        // On every interface: any address of this computer, but still no other name.
        let any = config("0.0.0.0:8080", &[]);
        assert!(host_allowed(&any, "192.168.1.5:8080"));
        assert!(!host_allowed(&any, "rebound.example:8080"));
        assert!(host_allowed(&any, "localhost:8080"));
        // A name on the default port (a reverse proxy in front).
        let proxied = config("127.0.0.1:7878", &["shop.example"]);
        assert!(host_allowed(&proxied, "shop.example"));
    }

    #[test]
    fn a_page_of_another_origin_is_refused() {
        let c = config("127.0.0.1:7878", &[]);
        let h = |host, origin| check_request(&c, &headers(host, origin));
        assert!(h(Some("127.0.0.1:7878"), Some("http://127.0.0.1:7878")).is_ok());
        assert!(h(Some("localhost:7878"), Some("http://localhost:7878")).is_ok());
        // Programs send no Origin.
        assert!(h(Some("127.0.0.1:7878"), None).is_ok());
        assert!(h(None, None).is_ok());
        let e = h(Some("127.0.0.1:7878"), Some("http://127.0.0.1:9000")).unwrap_err();
        assert!(e.contains("127.0.0.1:9000"), "{e}");
        assert!(h(Some("127.0.0.1:7878"), Some("null")).is_err());
        assert!(h(Some("127.0.0.1:7878"), Some("http://localhost:7878")).is_err());
        assert!(h(None, Some("http://127.0.0.1:7878")).is_err());
        let e = h(Some("evil.example:7878"), Some("http://evil.example:7878")).unwrap_err();
        assert!(e.contains("evil.example"), "{e}");
    }
}
