//! The page the binary carries (`web/dist` at build time, see `build.rs`), served as a
//! single-page app: a path that names no file gets `index.html`.

use axum::http::{header, StatusCode, Uri};
use axum::response::{IntoResponse, Response};

include!(concat!(env!("OUT_DIR"), "/page.rs"));

/// True when the binary was built after the page was.
pub(crate) fn built() -> bool {
    PAGE.iter().any(|(p, _)| *p == "index.html")
}

fn find(path: &str) -> Option<&'static [u8]> {
    PAGE.iter().find(|(p, _)| *p == path).map(|(_, b)| *b)
}

/// The file `uri` names, or the page itself for the app's own paths.
pub(crate) async fn serve(uri: Uri) -> Response {
    let path = uri.path().trim_start_matches('/');
    let path = if path.is_empty() { "index.html" } else { path };
    let (name, bytes) = match find(path) {
        Some(b) => (path, b),
        // `/assets/x.js` that is not there is a 404; `/anything` is the app.
        None if !path.rsplit('/').next().unwrap_or("").contains('.') => match find("index.html") {
            Some(b) => ("index.html", b),
            None => return StatusCode::NOT_FOUND.into_response(),
        },
        None => return (StatusCode::NOT_FOUND, format!("no such file: /{path}")).into_response(),
    };
    let mime = mime_guess::from_path(name).first_or_octet_stream();
    (
        [(header::CONTENT_TYPE, mime.essence_str().to_string())],
        bytes,
    )
        .into_response()
}
