//! The TCP listeners: accept connections, cap their number, hand each to its own task, and
//! stop them all on shutdown.

use crate::connection;
use crate::exec::Context;
use crate::shutdown::Shutdown;
use std::future::Future;
use std::sync::Arc;
use tokio::io::AsyncWriteExt;
use tokio::net::{TcpListener, TcpStream};
use tokio::sync::{Semaphore, broadcast, mpsc};

/// Most simultaneous connections per listener.
pub const MAX_CONNECTIONS: usize = 64;

/// Accept JSON connections on `listener` until `shutdown` resolves, then tell every connection
/// to stop and wait for them.
pub async fn run_json(listener: TcpListener, ctx: Context, shutdown: impl Future) {
    let refusal = format!(
        "{}\n",
        crate::result::error(format!(
            "too many connections (at most {MAX_CONNECTIONS}); try again later"
        ))
    );
    run(
        listener,
        ctx,
        shutdown,
        "JSON connection",
        refusal,
        connection::serve,
    )
    .await;
}

/// Accept connections on `listener` and serve each with `serve` in its own task, at most
/// [`MAX_CONNECTIONS`] at once (one more gets `refusal` and is closed), until `shutdown`
/// resolves; then tell every connection to stop and wait for them. Shared by the JSON channel
/// and the text HMI.
pub async fn run<F, Fut>(
    listener: TcpListener,
    ctx: Context,
    shutdown: impl Future,
    what: &'static str,
    refusal: String,
    serve: F,
) where
    F: Fn(TcpStream, Context, Shutdown) -> Fut + Copy + Send + 'static,
    Fut: Future<Output = std::io::Result<()>> + Send + 'static,
{
    let (notify, _) = broadcast::channel(1);
    let (done_tx, mut done_rx) = mpsc::channel::<()>(1);
    let limit = Arc::new(Semaphore::new(MAX_CONNECTIONS));
    let accept = async {
        loop {
            let (mut socket, _peer) = match listener.accept().await {
                Ok(s) => s,
                Err(e) => {
                    eprintln!("mcm-gateway: accept of a {what} failed: {e}");
                    tokio::time::sleep(std::time::Duration::from_millis(50)).await;
                    continue;
                }
            };
            let Ok(permit) = limit.clone().try_acquire_owned() else {
                let _ = socket.write_all(refusal.as_bytes()).await;
                continue;
            };
            let ctx = ctx.clone();
            let shutdown = Shutdown::new(notify.subscribe());
            let done = done_tx.clone();
            tokio::spawn(async move {
                if let Err(e) = serve(socket, ctx, shutdown).await
                    && e.kind() != std::io::ErrorKind::BrokenPipe
                    && e.kind() != std::io::ErrorKind::ConnectionReset
                {
                    eprintln!("mcm-gateway: a {what} ended with an error: {e}");
                }
                drop(permit);
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
