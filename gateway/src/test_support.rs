//! Set-up shared by the unit tests that run the gateway against a bridge whose real-time core
//! is not running.

use crate::command::Context;
use crate::core_link::bridge::{Bridge, BridgeThread};
use mcm_shared::config::RobotConfig;
use mcm_shared::service::ServiceNames;
use std::sync::Arc;
use std::sync::atomic::{AtomicU32, Ordering};

static NEXT: AtomicU32 = AtomicU32::new(0);

/// A context with `cfg`, the default access rules and a bridge to a core that is not running,
/// under an instance name no other test uses (`<prefix>-<pid>-<n>`). Returns the context, the
/// bridge's thread (to stop at the end) and the instance name.
pub(crate) fn offline_context(prefix: &str, cfg: RobotConfig) -> (Context, BridgeThread, String) {
    let instance = format!(
        "{prefix}-{}-{}",
        std::process::id(),
        NEXT.fetch_add(1, Ordering::Relaxed)
    );
    let (bridge, thread) = Bridge::start(&ServiceNames::new(&instance).unwrap(), "/tmp");
    let ctx = Context::new(Arc::new(cfg), bridge, Default::default());
    (ctx, thread, instance)
}
