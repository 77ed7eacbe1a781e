//! The signals that stop the server (Ctrl-C, SIGTERM), registered before
//! any listener is announced, and the wait for them or for the scan thread
//! stopping on its own.

use super::shared::Shared;
use std::time::Duration;

/// The signals that stop the server, registered once.
pub struct StopSignals {
    #[cfg(unix)]
    terminate: Option<tokio::signal::unix::Signal>,
    #[cfg(unix)]
    interrupt: Option<tokio::signal::unix::Signal>,
}

impl StopSignals {
    /// Registers the handlers (inside the runtime). Where one cannot be
    /// registered, that signal keeps its default action.
    pub fn register() -> StopSignals {
        #[cfg(unix)]
        {
            use tokio::signal::unix::{signal, SignalKind};
            StopSignals {
                terminate: signal(SignalKind::terminate()).ok(),
                interrupt: signal(SignalKind::interrupt()).ok(),
            }
        }
        #[cfg(not(unix))]
        StopSignals {}
    }
}

/// Ctrl-C, SIGTERM, or the scan thread stopping on its own.
pub async fn wait_for_stop(shared: &Shared, signals: StopSignals) {
    #[cfg(unix)]
    let (terminate, interrupt) = {
        let wait = |signal: Option<tokio::signal::unix::Signal>| async move {
            match signal {
                Some(mut signal) => {
                    signal.recv().await;
                }
                None => std::future::pending::<()>().await,
            }
        };
        (wait(signals.terminate), wait(signals.interrupt))
    };
    #[cfg(not(unix))]
    let (terminate, interrupt) = {
        let StopSignals {} = signals;
        (std::future::pending::<()>(), async {
            let _ = tokio::signal::ctrl_c().await;
        })
    };
    let stopped = async {
        while !shared.stopping() {
            tokio::time::sleep(Duration::from_millis(50)).await;
        }
    };
    tokio::select! {
        () = interrupt => {}
        () = terminate => {}
        () = stopped => {}
    }
}
