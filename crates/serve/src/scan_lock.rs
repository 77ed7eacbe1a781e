//! The locks the scan thread shares with the servers' threads.
//!
//! On Linux they inherit priority (futex PI locks): a server thread that
//! holds one while the scan thread waits runs at the scan thread's
//! priority until it lets go. With plain locks, a holder that the
//! scheduler put aside among the other server threads kept a `--realtime`
//! scan waiting for milliseconds on a loaded machine (a trend's samples,
//! the published image). Elsewhere they are the standard library's.

#[cfg(target_os = "linux")]
mod platform {
    pub type ScanLock<T> = priority_inheriting_lock::PriorityInheritingLock<T>;
    pub type ScanGuard<'a, T> = priority_inheriting_lock::PriorityInheritingLockGuard<'a, T>;

    pub fn new<T>(value: T) -> ScanLock<T> {
        ScanLock::new(value)
    }

    pub fn lock<T>(lock: &ScanLock<T>) -> ScanGuard<'_, T> {
        lock.lock()
    }
}

#[cfg(not(target_os = "linux"))]
mod platform {
    pub type ScanLock<T> = std::sync::Mutex<T>;
    pub type ScanGuard<'a, T> = std::sync::MutexGuard<'a, T>;

    pub fn new<T>(value: T) -> ScanLock<T> {
        ScanLock::new(value)
    }

    /// A lock whose holder panicked is still usable: the data is plain
    /// values.
    pub fn lock<T>(lock: &ScanLock<T>) -> ScanGuard<'_, T> {
        lock.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
    }
}

pub use platform::{lock, new, ScanGuard, ScanLock};
