//! Ctrl-C in long calls. Python runs its signal handlers (SIGINT's raises
//! KeyboardInterrupt) only on the main thread and only when it runs
//! Python code, which a call into Rust with the GIL released never does:
//! so the work runs on a helper thread while the calling thread waits in
//! short steps and asks Python for pending signals in between. A handler
//! that raises sets the work's cancel flag; the work then ends as the CLI
//! ends on Ctrl-C (the render finishes its pass and saves its film and
//! checkpoint), and the caller raises the handler's exception after that.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::time::Duration;

use pyo3::prelude::*;

/// How often the waiting thread looks for signals.
const POLL: Duration = Duration::from_millis(50);

/// `work()` with the GIL released, cancellable through `cancel` by a
/// Python signal handler that raises (Ctrl-C). Returns what `work`
/// returned and the exception to raise once its results are saved
/// (`None` when no signal came). A panic in `work` is resumed here.
pub(crate) fn interruptible<T: Send>(
    py: Python<'_>,
    cancel: &AtomicBool,
    work: impl FnOnce() -> T + Send,
) -> (T, Option<PyErr>) {
    std::thread::scope(|s| {
        let (done_tx, done_rx) = mpsc::channel::<()>();
        let worker = s.spawn(move || {
            let value = work();
            let _ = done_tx.send(());
            value
        });
        let mut raised = None;
        let mut rx = done_rx;
        loop {
            // The receiver is moved to the GIL-free closure and back (it
            // is Send, not Sync).
            let (got, back) = py.detach(move || (rx.recv_timeout(POLL), rx));
            rx = back;
            match got {
                Err(mpsc::RecvTimeoutError::Timeout) => {}
                // Sent, or the worker panicked (its sender dropped).
                _ => break,
            }
            if raised.is_none() {
                if let Err(e) = py.check_signals() {
                    cancel.store(true, Ordering::Relaxed);
                    raised = Some(e);
                }
            }
        }
        let value = match worker.join() {
            Ok(v) => v,
            Err(panic) => std::panic::resume_unwind(panic),
        };
        (value, raised)
    })
}
