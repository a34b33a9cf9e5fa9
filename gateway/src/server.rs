//! The TCP listeners: accept connections, cap their number, hand each to its own task, and
//! stop them all on shutdown.

use crate::connection;
use crate::exec::Context;
use crate::shutdown::Shutdown;
use std::future::Future;
use std::sync::Arc;
use tokio::io::AsyncWriteExt;
use tokio::net::TcpListener;
use tokio::sync::{Semaphore, broadcast, mpsc};

/// Most simultaneous connections per listener.
pub const MAX_CONNECTIONS: usize = 64;

/// Accept JSON connections on `listener` until `shutdown` resolves, then tell every connection
/// to stop and wait for them.
pub async fn run_json(listener: TcpListener, ctx: Context, shutdown: impl Future) {
    let (notify, _) = broadcast::channel(1);
    let (done_tx, mut done_rx) = mpsc::channel::<()>(1);
    let limit = Arc::new(Semaphore::new(MAX_CONNECTIONS));
    tokio::select! {
        () = accept_loop(&listener, &ctx, &notify, &done_tx, &limit) => {}
        _ = shutdown => {}
    }
    drop(notify);
    drop(done_tx);
    let _ = done_rx.recv().await;
}

async fn accept_loop(
    listener: &TcpListener,
    ctx: &Context,
    notify: &broadcast::Sender<()>,
    done: &mpsc::Sender<()>,
    limit: &Arc<Semaphore>,
) {
    loop {
        let (mut socket, _peer) = match listener.accept().await {
            Ok(s) => s,
            Err(e) => {
                eprintln!("mcm-gateway: accept failed: {e}");
                tokio::time::sleep(std::time::Duration::from_millis(50)).await;
                continue;
            }
        };
        let Ok(permit) = limit.clone().try_acquire_owned() else {
            let msg = crate::result::error(format!(
                "too many connections (at most {MAX_CONNECTIONS}); try again later"
            ));
            let _ = socket.write_all(format!("{msg}\n").as_bytes()).await;
            continue;
        };
        let ctx = ctx.clone();
        let shutdown = Shutdown::new(notify.subscribe());
        let done = done.clone();
        tokio::spawn(async move {
            if let Err(e) = connection::serve(socket, ctx, shutdown).await
                && e.kind() != std::io::ErrorKind::BrokenPipe
                && e.kind() != std::io::ErrorKind::ConnectionReset
            {
                eprintln!("mcm-gateway: connection ended with an error: {e}");
            }
            drop(permit);
            drop(done);
        });
    }
}
