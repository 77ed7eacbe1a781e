//! How the scan thread tells a poller that outputs changed without taking
//! a lock a server thread may hold. tokio's `Notify` (and any task waker)
//! takes plain mutexes when a task waits, which a `--realtime` scan could
//! then wait on behind a preempted server thread (docs/serve.md, "A steady
//! period"). On Linux the signal is an eventfd: the scan thread adds to
//! its counter with one non-blocking `write(2)`, and the poller's task
//! waits for it through tokio's reactor. Elsewhere (no priority-inheriting
//! locks there either) it is a `Notify`.

#[cfg(target_os = "linux")]
pub use linux::Signal;

#[cfg(not(target_os = "linux"))]
pub use other::Signal;

#[cfg(target_os = "linux")]
mod linux {
    use std::io;
    use std::os::fd::{AsRawFd, FromRawFd, OwnedFd};
    use tokio::io::unix::AsyncFd;

    /// The scan thread's side: a non-blocking eventfd (None when the
    /// system gave none: then changes wait for the next poll).
    #[derive(Debug)]
    pub struct Signal {
        fd: Option<OwnedFd>,
    }

    impl Signal {
        pub fn new() -> Signal {
            // SAFETY: eventfd takes no pointers; a descriptor it returns is
            // new and owned here alone.
            let raw = unsafe { libc::eventfd(0, libc::EFD_NONBLOCK | libc::EFD_CLOEXEC) };
            Signal {
                // SAFETY: `raw` is a descriptor eventfd just opened.
                fd: (raw >= 0).then(|| unsafe { OwnedFd::from_raw_fd(raw) }),
            }
        }

        /// Wakes the poller (scan thread): one system call, no lock.
        pub fn raise(&self) {
            if let Some(fd) = &self.fd {
                let one: u64 = 1;
                // SAFETY: writes the 8 bytes of `one` to the open eventfd;
                // a full counter (EAGAIN) already means "woken".
                let _ = unsafe { libc::write(fd.as_raw_fd(), std::ptr::addr_of!(one).cast(), 8) };
            }
        }

        /// The poller's side (inside the runtime).
        pub fn waiter(&self) -> Waiter {
            let registered = self.fd.as_ref().and_then(|fd| fd.try_clone().ok()).and_then(|fd| {
                // SAFETY: `fd` (a duplicate this waiter owns) stays open
                // and the same until the `AsyncFd` is dropped.
                unsafe { AsyncFd::register(fd) }.ok()
            });
            Waiter { fd: registered }
        }
    }

    /// The poller's side of a `Signal`.
    pub struct Waiter {
        fd: Option<AsyncFd<OwnedFd>>,
    }

    impl Waiter {
        /// Returns when the scan thread raised the signal (never, without
        /// an eventfd).
        pub async fn wait(&self) {
            let Some(fd) = &self.fd else {
                return std::future::pending().await;
            };
            loop {
                let Ok(mut guard) = fd.readable().await else {
                    return std::future::pending().await;
                };
                let mut count = [0u8; 8];
                let read = guard.try_io(|fd| {
                    // SAFETY: reads at most 8 bytes into `count` from the
                    // open eventfd (resetting its counter).
                    let n = unsafe { libc::read(fd.get_ref().as_raw_fd(), count.as_mut_ptr().cast(), 8) };
                    usize::try_from(n).map_err(|_| io::Error::last_os_error())
                });
                if let Ok(Ok(_)) = read {
                    return;
                }
            }
        }
    }
}

#[cfg(not(target_os = "linux"))]
mod other {
    use std::sync::Arc;

    #[derive(Debug, Default)]
    pub struct Signal {
        notify: Arc<tokio::sync::Notify>,
    }

    impl Signal {
        pub fn new() -> Signal {
            Signal::default()
        }

        pub fn raise(&self) {
            self.notify.notify_one();
        }

        pub fn waiter(&self) -> Waiter {
            Waiter {
                notify: Arc::clone(&self.notify),
            }
        }
    }

    pub struct Waiter {
        notify: Arc<tokio::sync::Notify>,
    }

    impl Waiter {
        pub async fn wait(&self) {
            self.notify.notified().await;
        }
    }
}
