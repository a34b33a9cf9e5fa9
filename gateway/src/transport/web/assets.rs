//! The page's files: everything under `gateway/web/`, embedded in the binary when it is built
//! (also in debug builds), so that the gateway serves the pendant without npm or a file
//! system path. `/` is `index.html`; the content type follows the file's extension.

use axum::http::{StatusCode, Uri, header};
use axum::response::{IntoResponse, Response};
use rust_embed::RustEmbed;

#[derive(RustEmbed)]
#[folder = "web/"]
struct Files;

/// The file at `uri`'s path, or 404 naming it.
pub async fn serve(uri: Uri) -> Response {
    let path = uri.path().trim_start_matches('/');
    let path = if path.is_empty() { "index.html" } else { path };
    match Files::get(path) {
        Some(file) => (
            [
                (header::CONTENT_TYPE, file.metadata.mimetype().to_string()),
                // The page must never run old code against a newer gateway.
                (header::CACHE_CONTROL, "no-cache".to_string()),
            ],
            file.data,
        )
            .into_response(),
        None => (
            StatusCode::NOT_FOUND,
            format!("no such file on the pendant: /{path}\n"),
        )
            .into_response(),
    }
}

/// The embedded files' paths (for the tests).
#[cfg(test)]
pub fn paths() -> Vec<String> {
    Files::iter().map(|p| p.to_string()).collect()
}
