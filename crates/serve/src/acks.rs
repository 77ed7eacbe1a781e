//! Answering a write only once it is applied, as a CPU answers a request
//! after the END processing that carried it out: every queued write gets a
//! ticket (the number of the batch of writes the scan thread will take it
//! in), and the scan thread, after applying a batch and publishing the
//! image that shows it, marks that batch applied and wakes the writers
//! waiting for it. A read after the answer then sees the write.
//!
//! A writer waits at most `WRITE_WAIT` (a scan that takes longer, or an
//! engine that no longer scans) and not past a stop: then it is told the
//! write was not applied in time, and its client gets the protocol's
//! error, never an acknowledgement. Writers wait on a thread (the serial
//! line) or as a task (Modbus TCP, MELSEC, HTTP, OPC UA): a task that
//! waits holds no thread of the runtime.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Condvar, Mutex};
use std::time::{Duration, Instant};

/// How long a writer waits for its write to be applied: the rest of the
/// scan in progress, however slow, is far shorter (an idle or stopped PLC
/// applies a write at once); an online change that compiles the new
/// program on the scan thread (`--engine aot`, `c`) may take longer, and
/// its writers are told the write was not applied in time.
pub const WRITE_WAIT: Duration = Duration::from_secs(5);

/// The batch a queued write is applied in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[must_use = "a write is answered once its ticket is applied"]
pub struct Ticket(pub(crate) u64);

/// Why a queued write was not answered as applied.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NotApplied {
    /// The server is stopping (or its program could not run): the scan
    /// thread applies nothing more.
    Stopping,
    /// Not applied within `WRITE_WAIT`.
    TimedOut,
}

/// The batches applied so far, and the writers waiting for theirs.
#[derive(Default)]
pub struct Acks {
    applied: Mutex<u64>,
    /// Threads that wait.
    changed: Condvar,
    /// Tasks that wait.
    notify: tokio::sync::Notify,
    stopping: AtomicBool,
}

/// The lock of a plain number: a holder that panicked left a number.
fn lock_applied(mutex: &Mutex<u64>) -> std::sync::MutexGuard<'_, u64> {
    mutex.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
}

impl Acks {
    /// Batch `batch` (and every one before it) is applied and published.
    pub fn applied(&self, batch: u64) {
        let mut applied = lock_applied(&self.applied);
        if batch > *applied {
            *applied = batch;
        }
        drop(applied);
        self.changed.notify_all();
        self.notify.notify_waiters();
    }

    /// Nothing more will be applied: every waiting writer is told so.
    pub fn stop(&self) {
        self.stopping.store(true, Ordering::Relaxed);
        // Taken and let go so that a thread between its check and its wait
        // is waiting when the notification comes.
        drop(lock_applied(&self.applied));
        self.changed.notify_all();
        self.notify.notify_waiters();
    }

    /// Whether `ticket` is applied; `Err` when it never will be.
    fn settled(&self, ticket: Ticket) -> Option<Result<(), NotApplied>> {
        if *lock_applied(&self.applied) >= ticket.0 {
            Some(Ok(()))
        } else if self.stopping.load(Ordering::Relaxed) {
            Some(Err(NotApplied::Stopping))
        } else {
            None
        }
    }

    /// Blocks the calling thread until `ticket` is applied (at most
    /// `WRITE_WAIT`).
    pub fn wait(&self, ticket: Ticket) -> Result<(), NotApplied> {
        self.wait_within(ticket, WRITE_WAIT)
    }

    fn wait_within(&self, ticket: Ticket, within: Duration) -> Result<(), NotApplied> {
        let deadline = Instant::now() + within;
        let mut applied = lock_applied(&self.applied);
        loop {
            if *applied >= ticket.0 {
                return Ok(());
            }
            if self.stopping.load(Ordering::Relaxed) {
                return Err(NotApplied::Stopping);
            }
            let now = Instant::now();
            if now >= deadline {
                return Err(NotApplied::TimedOut);
            }
            applied = match self.changed.wait_timeout(applied, deadline - now) {
                Ok((guard, _)) => guard,
                Err(poisoned) => poisoned.into_inner().0,
            };
        }
    }

    /// Waits (as a task) until `ticket` is applied (at most `WRITE_WAIT`).
    pub async fn wait_async(&self, ticket: Ticket) -> Result<(), NotApplied> {
        let waiting = async {
            loop {
                let mut notified = std::pin::pin!(self.notify.notified());
                // Registered before the check: a batch applied between the
                // check and the wait still wakes it.
                notified.as_mut().enable();
                if let Some(settled) = self.settled(ticket) {
                    return settled;
                }
                notified.await;
            }
        };
        tokio::time::timeout(WRITE_WAIT, waiting)
            .await
            .unwrap_or(Err(NotApplied::TimedOut))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Arc;

    #[test]
    fn a_writer_waits_for_its_batch_and_a_stop_ends_every_wait() {
        let acks = Arc::new(Acks::default());
        acks.applied(3);
        assert_eq!(acks.wait(Ticket(2)), Ok(()), "applied already");
        let started = Arc::new(std::sync::Barrier::new(2));
        let waiter = {
            let (acks, started) = (Arc::clone(&acks), Arc::clone(&started));
            std::thread::spawn(move || {
                started.wait();
                acks.wait(Ticket(5))
            })
        };
        started.wait();
        acks.applied(4);
        assert_eq!(
            acks.wait_within(Ticket(5), Duration::from_millis(20)),
            Err(NotApplied::TimedOut),
            "batch 4 is not batch 5"
        );
        acks.applied(5);
        assert_eq!(waiter.join().ok(), Some(Ok(())));
        let runtime = tokio::runtime::Builder::new_current_thread()
            .enable_all()
            .build()
            .unwrap();
        runtime.block_on(async {
            // Polled while batch 6 is the last applied, so it waits; then
            // woken by batch 7, not by its time running out.
            let mut waiting = std::pin::pin!(acks.wait_async(Ticket(7)));
            acks.applied(6);
            let early = tokio::time::timeout(Duration::from_millis(20), waiting.as_mut()).await;
            assert!(early.is_err(), "batch 6 is not batch 7: {early:?}");
            acks.applied(7);
            let began = std::time::Instant::now();
            assert_eq!(waiting.await, Ok(()));
            assert!(began.elapsed() < WRITE_WAIT / 2, "woken by the batch");
        });
        let task = {
            let acks = Arc::clone(&acks);
            runtime.spawn(async move { acks.wait_async(Ticket(9)).await })
        };
        let stopper = {
            let acks = Arc::clone(&acks);
            std::thread::spawn(move || {
                std::thread::sleep(Duration::from_millis(20));
                acks.stop();
            })
        };
        assert_eq!(runtime.block_on(task).ok(), Some(Err(NotApplied::Stopping)));
        let _ = stopper.join();
        assert_eq!(acks.wait(Ticket(9)), Err(NotApplied::Stopping));
        let running = Acks::default();
        assert_eq!(
            running.wait_within(Ticket(1), Duration::from_millis(20)),
            Err(NotApplied::TimedOut),
            "a batch never applied"
        );
        assert_eq!(acks.wait(Ticket(5)), Ok(()), "what was applied stays applied");
    }
}
