//! HTTP/1.1 on one admitted web connection: the routes of the pendant, and the hand-over of a
//! page's WebSocket to [`super::socket`] on the same connection (so that it keeps its slot in
//! the port's table and stops with the server).

use super::arrivals::Arrivals;
use super::frames::Frames;
use super::own_names::OwnNames;
use super::{api, assets, socket};
use crate::command::Context;
use crate::transport::server::FAREWELL_TIMEOUT;
use crate::transport::server::admission::Slot;
use crate::transport::shutdown::Shutdown;
use axum::extract::ws::{WebSocket, WebSocketUpgrade};
use axum::extract::{Path as UrlPath, Request, State};
use axum::http::{StatusCode, header};
use axum::middleware::{Next, from_fn_with_state};
use axum::response::{IntoResponse, Response};
use axum::routing::get;
use axum::{Extension, Json, Router};
use hyper_util::rt::{TokioIo, TokioTimer};
use hyper_util::service::TowerToHyperService;
use std::net::SocketAddr;
use std::path::PathBuf;
use std::sync::{Arc, Mutex, PoisonError};
use std::time::Duration;
use tokio::net::TcpStream;
use tokio::sync::oneshot;

/// What the routes need.
struct Web {
    ctx: Context,
    instance: String,
    records_dir: PathBuf,
}

/// The pendant's routes and its state frames; cheap to clone.
#[derive(Clone)]
pub struct Routes {
    router: Router,
    frames: Frames,
}

impl Routes {
    /// The routes of the gateway `ctx` of MCM instance `instance`, on a port bound to `bound`.
    pub fn new(ctx: &Context, instance: &str, frames: Frames, bound: SocketAddr) -> Routes {
        let web = Arc::new(Web {
            ctx: ctx.clone(),
            instance: instance.to_string(),
            records_dir: PathBuf::from(&ctx.cfg.safety.flight_recorder_dir),
        });
        // Compressed: the assets and the API; not the WebSocket's upgrade.
        let compressed = Router::new()
            .route("/api/model", get(model))
            .route("/api/connections", get(connections))
            .route("/api/flight-records", get(records))
            .route("/api/flight-records/{name}", get(record))
            .fallback(assets::serve)
            .layer(tower_http::compression::CompressionLayer::new())
            .with_state(web);
        // Validated when the configuration was read.
        let configured = ctx.cfg.gateway.web.hosts().unwrap_or_default();
        let names = Arc::new(OwnNames::new(configured, bound.ip()));
        let router = Router::new()
            .route("/ws", get(upgrade))
            .merge(compressed)
            .layer(from_fn_with_state(names, own_names_only));
        Routes { router, frames }
    }
}

/// Every route: only a request addressed to one of the robot's own names is served; any
/// other gets 421 with the reason (a WebSocket is then not upgraded).
async fn own_names_only(State(names): State<Arc<OwnNames>>, req: Request, next: Next) -> Response {
    match names.check(req.headers(), req.uri()) {
        Ok(()) => next.run(req).await,
        Err(why) => (StatusCode::MISDIRECTED_REQUEST, format!("{why}\n")).into_response(),
    }
}

/// The connection a request came on: the peer, and where a WebSocket goes.
#[derive(Clone)]
struct Conn {
    upgrade: Arc<Mutex<Option<oneshot::Sender<WebSocket>>>>,
}

async fn model(State(web): State<Arc<Web>>) -> Json<serde_json::Value> {
    Json(api::model(&web.ctx.cfg, &web.instance))
}

async fn connections(State(web): State<Arc<Web>>) -> Json<serde_json::Value> {
    let owner = web.ctx.bridge.owner();
    Json(api::connections(&web.ctx.clients.list(), owner))
}

async fn records(State(web): State<Arc<Web>>) -> Json<serde_json::Value> {
    let (dir, instance) = (web.records_dir.clone(), web.instance.clone());
    let list = tokio::task::spawn_blocking(move || api::records_json(&dir, &instance)).await;
    Json(list.unwrap_or_else(|_| serde_json::json!({"records": []})))
}

async fn record(State(web): State<Arc<Web>>, UrlPath(name): UrlPath<String>) -> Response {
    let not_found = |why: String| (StatusCode::NOT_FOUND, format!("{why}\n")).into_response();
    let Some(path) = api::record_path(&web.records_dir, &web.instance, &name) else {
        return not_found(format!(
            "{name:?} is not a flight-recorder file of instance {} (mcm-{}-<unix ms>-<check>.csv)",
            web.instance, web.instance
        ));
    };
    let read = tokio::task::spawn_blocking(move || std::fs::read(&path).map_err(|e| (path, e)));
    match read
        .await
        .unwrap_or_else(|e| Err((PathBuf::new(), std::io::Error::other(e))))
    {
        Ok(bytes) => (
            [
                (header::CONTENT_TYPE, "text/csv; charset=utf-8".to_string()),
                (
                    header::CONTENT_DISPOSITION,
                    format!("attachment; filename=\"{name}\""),
                ),
            ],
            bytes,
        )
            .into_response(),
        Err((path, e)) => not_found(format!("cannot read {}: {e}", path.display())),
    }
}

/// Whether a WebSocket request with these headers comes from the pendant's own page: a browser
/// always sends `Origin`, and it must be this server (`Host`), so that a page from elsewhere
/// that an operator's browser happens to show cannot drive the arm through the operator's
/// network position (cross-site WebSocket hijacking). A request without `Origin` is not from a
/// browser page (a program, which could connect to the JSON port as well). `Host` itself is one
/// of the robot's own names ([`super::own_names`]), so the origin is one too.
pub fn same_origin(headers: &axum::http::HeaderMap) -> Result<(), String> {
    let Some(origin) = headers.get(header::ORIGIN) else {
        return Ok(());
    };
    let origin = origin.to_str().unwrap_or("");
    let host = headers
        .get(header::HOST)
        .and_then(|h| h.to_str().ok())
        .unwrap_or("");
    let origin_host = origin
        .strip_prefix("http://")
        .or_else(|| origin.strip_prefix("https://"))
        .unwrap_or("");
    if !host.is_empty() && origin_host.eq_ignore_ascii_case(host) {
        Ok(())
    } else {
        Err(format!(
            "WebSocket refused: a page from {origin:?} may not use the pendant of {host:?}; \
             open the pendant's own page (http://{host}/)"
        ))
    }
}

async fn upgrade(
    ws: WebSocketUpgrade,
    headers: axum::http::HeaderMap,
    Extension(conn): Extension<Conn>,
) -> Response {
    if let Err(why) = same_origin(&headers) {
        return (StatusCode::FORBIDDEN, format!("{why}\n")).into_response();
    }
    let taken = conn
        .upgrade
        .lock()
        .unwrap_or_else(PoisonError::into_inner)
        .take();
    let Some(tx) = taken else {
        return (StatusCode::CONFLICT, "one WebSocket per connection\n").into_response();
    };
    // Longer than a command may be, so that the connection's own framing answers an
    // over-long command with its reason instead of the socket just closing.
    let max = 2 * mcm_shared::protocol::MAX_COMMAND_BYTES;
    ws.max_message_size(max)
        .max_frame_size(max)
        .on_upgrade(move |socket| async move {
            let _ = tx.send(socket);
        })
}

/// Serve one admitted web connection: HTTP requests until the peer closes it, the server
/// shuts down, the connection is evicted or has lived `idle_timeout_s`; a WebSocket upgrade
/// becomes the page's session for the rest of the connection's life.
pub async fn serve(
    stream: TcpStream,
    ctx: Context,
    mut shutdown: Shutdown,
    mut slot: Slot,
    routes: Routes,
) -> std::io::Result<()> {
    stream.set_nodelay(true)?;
    let peer: SocketAddr = stream.peer_addr()?;
    let (tx, rx) = oneshot::channel();
    let conn = Conn {
        upgrade: Arc::new(Mutex::new(Some(tx))),
    };
    let app = routes.router.clone().layer(Extension(conn));
    let arrivals = Arrivals::default();
    let limits = &ctx.cfg.gateway.connections;
    let mut http = Box::pin(
        hyper::server::conn::http1::Builder::new()
            .timer(TokioTimer::new())
            .header_read_timeout(Duration::from_secs_f64(limits.line_timeout_s))
            .serve_connection(
                TokioIo::new(arrivals.watch(stream)),
                TowerToHyperService::new(app),
            )
            .with_upgrades(),
    );
    let life = tokio::time::sleep(Duration::from_secs_f64(limits.idle_timeout_s));
    let ended = tokio::select! {
        r = http.as_mut() => Some(r),
        () = shutdown.recv() => None,
        _ = slot.evicted() => None,
        () = life => None,
    };
    if ended.is_none() {
        // Finish the request in flight, then close.
        http.as_mut().graceful_shutdown();
        let _ = tokio::time::timeout(FAREWELL_TIMEOUT, http.as_mut()).await;
        return Ok(());
    }
    // Dropping the connection drops the routes it held, with the WebSocket's sender unless a
    // request took it: then the upgraded socket arrives.
    drop(http);
    match rx.await {
        Ok(ws) => {
            let frames = routes.frames.clone();
            socket::session(ws, peer, ctx, shutdown, slot, frames, arrivals).await
        }
        Err(_) => Ok(()),
    }
}
