//! What the scan thread and the servers share: the image as the latest scan
//! left it (servers read this copy, never the live image), the host writes
//! waiting for the next scan, the scan statistics, and the stop flag.

use ladder_runtime::Memory;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Mutex, MutexGuard};
use std::time::Duration;

/// A write from a client, applied as a host write before the next scan.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HostWrite {
    /// Xn of the input image.
    Input(u32, bool),
    Output(u32, bool),
    Relay(u32, bool),
    Data(u32, i16),
    /// Any device, as `ladderc run --set` writes it.
    Set(crate::host_device::HostDevice, i32),
    Force(ladder_runtime::BitArea, u32, bool),
    Unforce(ladder_runtime::BitArea, u32),
}

/// Scan timing since the start.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Stats {
    pub scans: u64,
    pub last: Duration,
    pub min: Option<Duration>,
    pub max: Duration,
    pub total: Duration,
    /// The largest difference between a scan's start and its due time.
    pub jitter: Duration,
    /// Scans that started after the next one was due.
    pub overruns: u64,
}

impl Stats {
    pub fn average(&self) -> Duration {
        if self.scans == 0 {
            Duration::ZERO
        } else {
            self.total.div_f64(self.scans as f64)
        }
    }
}

pub struct Shared {
    image: Mutex<Box<Memory>>,
    /// A program waiting to replace the running one between two scans.
    pending: Mutex<Option<super::change::Loaded>>,
    /// Programs swapped in so far.
    swaps: std::sync::atomic::AtomicU64,
    writes: Mutex<Vec<HostWrite>>,
    stats: Mutex<Stats>,
    stop: AtomicBool,
}

impl Default for Shared {
    fn default() -> Self {
        Shared {
            image: Mutex::new(Memory::new_boxed()),
            pending: Mutex::new(None),
            swaps: std::sync::atomic::AtomicU64::new(0),
            writes: Mutex::new(Vec::new()),
            stats: Mutex::new(Stats::default()),
            stop: AtomicBool::new(false),
        }
    }
}

/// A lock whose holder panicked is still usable: the data is plain values.
fn lock<T>(mutex: &Mutex<T>) -> MutexGuard<'_, T> {
    mutex.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
}

impl Shared {
    /// The image as the latest scan left it.
    pub fn image(&self) -> MutexGuard<'_, Box<Memory>> {
        lock(&self.image)
    }

    pub fn publish(&self, image: &Memory) {
        **lock(&self.image) = *image;
    }

    pub fn queue(&self, writes: Vec<HostWrite>) {
        lock(&self.writes).extend(writes);
    }

    pub fn take_writes(&self) -> Vec<HostWrite> {
        std::mem::take(&mut *lock(&self.writes))
    }

    pub fn stats(&self) -> Stats {
        *lock(&self.stats)
    }

    pub fn update_stats(&self, update: impl FnOnce(&mut Stats)) {
        update(&mut lock(&self.stats));
    }

    /// Hands a compiled program to the scan thread; false (and nothing
    /// changes) while another one is still waiting to be swapped in.
    pub fn offer(&self, program: super::change::Loaded) -> bool {
        let mut pending = lock(&self.pending);
        if pending.is_some() {
            return false;
        }
        *pending = Some(program);
        true
    }

    pub fn take_program(&self) -> Option<super::change::Loaded> {
        lock(&self.pending).take()
    }

    pub fn swapped(&self) {
        self.swaps.fetch_add(1, Ordering::Relaxed);
    }

    pub fn swaps(&self) -> u64 {
        self.swaps.load(Ordering::Relaxed)
    }

    pub fn stop(&self) {
        self.stop.store(true, Ordering::Relaxed);
    }

    pub fn stopping(&self) -> bool {
        self.stop.load(Ordering::Relaxed)
    }
}
