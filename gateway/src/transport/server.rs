//! The TCP listeners of the JSON port ([`super::json`]) and the HMI port ([`super::hmi`]):
//! accept connections, admit them within the limits of `[gateway.connections]` ([`admission`]:
//! per-peer cap, total cap, loopback reserve, eviction of the longest-idle connection, never the
//! one that controls the arm), hand each to its own task, and stop them all on shutdown. What
//! else both ports' connections share: their time limits ([`timeouts`]) and the bounded last
//! line ([`farewell`], [`FAREWELL_TIMEOUT`]).

pub(crate) mod admission;
pub(crate) mod timeouts;

use crate::command::Context;
use crate::transport::shutdown::Shutdown;
use admission::{Shared, Slot};
use std::future::Future;
use std::net::IpAddr;
use std::sync::Arc;
use std::time::Duration;
use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::net::{TcpListener, TcpStream};
use tokio::sync::{Semaphore, broadcast, mpsc};

/// How long an evicted connection may take to say why and close before it is dropped.
pub const EVICT_GRACE: Duration = Duration::from_secs(3);
/// How long a connection's last line may take to be written: a farewell (timeout, eviction,
/// refusal; the peer's remaining bytes are then drained as long again, so that the line is
/// not lost to a reset) or the last words on shutdown (a client that does not read does not
/// hold the shutdown up).
pub const FAREWELL_TIMEOUT: Duration = Duration::from_secs(1);
/// Most refused connections being told why at once; beyond it they are closed silently.
const MAX_REFUSING: usize = 64;

/// How one port admits and answers connections.
#[derive(Debug, Clone, Copy)]
pub struct Port {
    /// What a connection is called in the log, e.g. "JSON connection".
    pub what: &'static str,
    /// The one line (with its line end) that tells a refused peer why.
    pub refusal: fn(&str) -> String,
    /// Which peers may use the loopback reserve ([`admission::is_loopback`]; tests that need
    /// "remote" peers on one machine narrow it).
    pub is_local: fn(IpAddr) -> bool,
}

/// Write `line`, close our side, then drain what the peer still sends (bounded in time), so
/// that the line reaches a peer that is still writing instead of being lost to a reset.
pub async fn farewell<R, W>(rd: &mut R, wr: &mut W, line: &[u8])
where
    R: AsyncReadExt + Unpin,
    W: AsyncWriteExt + Unpin,
{
    let say = async {
        wr.write_all(line).await?;
        wr.shutdown().await
    };
    if let Ok(Ok(())) = tokio::time::timeout(FAREWELL_TIMEOUT, say).await {
        let mut sink = [0u8; 1024];
        let drain = async { while matches!(rd.read(&mut sink).await, Ok(n) if n > 0) {} };
        let _ = tokio::time::timeout(FAREWELL_TIMEOUT, drain).await;
    }
}

/// Accept connections on `listener` and serve each with `serve` in its own task, within the
/// limits of `ctx.cfg.gateway.connections`, until `shutdown` resolves; then tell every
/// connection to stop and wait for them. Shared by the JSON channel and the text HMI. The
/// caller settles what is known of the core before it resolves `shutdown`
/// ([`crate::core_link::lifecycle::settle`], once for every transport), so that each
/// connection's last words tell it first.
pub async fn run<F, Fut>(
    listener: TcpListener,
    ctx: Context,
    shutdown: impl Future,
    port: Port,
    serve: F,
) where
    F: Fn(TcpStream, Context, Shutdown, Slot) -> Fut + Clone + Send + 'static,
    Fut: Future<Output = std::io::Result<()>> + Send + 'static,
{
    let table = Shared::new(ctx.cfg.gateway.connections.clone());
    run_with(listener, ctx, shutdown, port, serve, table).await;
}

/// [`run`] with limits of its own instead of `[gateway.connections]` (the web port's per-peer
/// cap is `[gateway.web] max_per_peer`: a browser opens several connections for one page).
pub async fn run_limited<F, Fut>(
    listener: TcpListener,
    ctx: Context,
    shutdown: impl Future,
    port: Port,
    limits: mcm_shared::config::ConnectionLimits,
    serve: F,
) where
    F: Fn(TcpStream, Context, Shutdown, Slot) -> Fut + Clone + Send + 'static,
    Fut: Future<Output = std::io::Result<()>> + Send + 'static,
{
    run_with(listener, ctx, shutdown, port, serve, Shared::new(limits)).await;
}

/// [`run`] with the port's connection table given (tests watch it).
async fn run_with<F, Fut>(
    listener: TcpListener,
    ctx: Context,
    shutdown: impl Future,
    port: Port,
    serve: F,
    table: Shared,
) where
    F: Fn(TcpStream, Context, Shutdown, Slot) -> Fut + Clone + Send + 'static,
    Fut: Future<Output = std::io::Result<()>> + Send + 'static,
{
    let what = port.what;
    let (notify, _) = broadcast::channel(1);
    let (done_tx, mut done_rx) = mpsc::channel::<()>(1);
    let refusing = Arc::new(Semaphore::new(MAX_REFUSING));
    let accept = async {
        loop {
            let (socket, peer) = match listener.accept().await {
                Ok(s) => s,
                Err(e) => {
                    eprintln!("mcm-gateway: accept of a {what} failed: {e}");
                    tokio::time::sleep(Duration::from_millis(50)).await;
                    continue;
                }
            };
            let ip = peer.ip().to_canonical();
            let owner = ctx.bridge.owner();
            let admitted =
                table
                    .lock()
                    .admit(ip, (port.is_local)(ip), tokio::time::Instant::now(), owner);
            let admission::Admitted { id, evict, .. } = match admitted {
                Ok(a) => a,
                Err(reason) => {
                    refuse(socket, (port.refusal)(&reason), &refusing);
                    continue;
                }
            };
            let mut kill = evict.clone();
            let slot = Slot::new(id, table.clone(), evict);
            let ctx = ctx.clone();
            let shutdown = Shutdown::new(notify.subscribe());
            let done = done_tx.clone();
            let serve = serve.clone();
            tokio::spawn(async move {
                let evicted_long_ago = async {
                    if kill.wait_for(Option::is_some).await.is_err() {
                        std::future::pending::<()>().await;
                    }
                    tokio::time::sleep(EVICT_GRACE).await;
                };
                let result = tokio::select! {
                    r = serve(socket, ctx, shutdown, slot) => r,
                    () = evicted_long_ago => Ok(()),
                };
                if let Err(e) = result
                    && e.kind() != std::io::ErrorKind::BrokenPipe
                    && e.kind() != std::io::ErrorKind::ConnectionReset
                {
                    eprintln!("mcm-gateway: a {what} ended with an error: {e}");
                }
                drop(done);
            });
        }
    };
    tokio::select! {
        () = accept => {}
        _ = shutdown => {}
    }
    drop(notify);
    drop(done_tx);
    let _ = done_rx.recv().await;
}

/// Tell a refused peer why in a task of its own (the accept loop never waits on a peer), at
/// most [`MAX_REFUSING`] at once.
fn refuse(socket: TcpStream, line: String, refusing: &Arc<Semaphore>) {
    let Ok(permit) = refusing.clone().try_acquire_owned() else {
        return;
    };
    tokio::spawn(async move {
        let (mut rd, mut wr) = socket.into_split();
        farewell(&mut rd, &mut wr, line.as_bytes()).await;
        drop(permit);
    });
}

#[cfg(test)]
mod tests;
