//! What the scan thread and the servers share: the image as the latest scan
//! left it (servers read this copy, never the live image), the host writes
//! waiting for the next scan, the scan statistics, the RUN/STOP switch and
//! breakpoints, the drawing of the running program, the recorders of the
//! trend, and the stop flag.

use super::control::Control;
use super::view::LadderView;
use crate::host_device::HostDevice;
use ladder_runtime::Memory;
use std::collections::VecDeque;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Condvar, Mutex, MutexGuard, Weak};
use std::time::{Duration, Instant};

/// Bytes of samples a recorder keeps for its client at most (older ones
/// are lost and counted): at a 10 ms period and 256 watched devices, about
/// two and a half seconds, twenty-five times the push period.
const RECORDER_BYTES: usize = 1 << 20;
/// Event streams served at once by default.
pub const MOST_EVENT_STREAMS: usize = 64;
/// A recorder whose client took nothing for this long is dropped (its
/// samples freed, its stream ended): a client that does not read.
pub const RECORDER_STALL: Duration = Duration::from_secs(10);

/// The values of some devices after every scan, for one client's trend:
/// the scan thread appends, the client takes them, so a pulse that lasts
/// one scan is never lost between two pushes.
pub struct Recorder {
    pub devices: Vec<HostDevice>,
    samples: Mutex<VecDeque<Sample>>,
    /// Samples kept at most (`RECORDER_BYTES` of them).
    capacity: usize,
    lost: std::sync::atomic::AtomicU64,
    /// When the client last took its samples.
    taken: Mutex<Instant>,
    /// Dropped for not taking them (`RECORDER_STALL`).
    dropped: AtomicBool,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Sample {
    pub scan: u64,
    /// Milliseconds since the server started.
    pub time_ms: u64,
    pub values: Vec<i32>,
}

impl Recorder {
    /// The samples since the last call, and how many were lost since.
    pub fn take(&self) -> (Vec<Sample>, u64) {
        *lock(&self.taken) = Instant::now();
        let samples = std::mem::take(&mut *lock(&self.samples)).into();
        (samples, self.lost.swap(0, Ordering::Relaxed))
    }

    /// Whether the client was dropped for not reading (its stream ends).
    pub fn dropped(&self) -> bool {
        self.dropped.load(Ordering::Relaxed)
    }
}

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

impl HostWrite {
    /// What the write writes, whatever value: a later write with the same
    /// key overwrites every byte this one wrote.
    fn key(self) -> WriteKey {
        match self {
            HostWrite::Input(n, _) => WriteKey::Input(n),
            HostWrite::Output(n, _) => WriteKey::Output(n),
            HostWrite::Relay(n, _) => WriteKey::Relay(n),
            HostWrite::Data(n, _) => WriteKey::Data(n),
            HostWrite::Set(device, _) => WriteKey::Set(device),
            HostWrite::Force(area, n, _) => WriteKey::Force(area, n),
            HostWrite::Unforce(area, n) => WriteKey::Unforce(area, n),
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum WriteKey {
    Input(u32),
    Output(u32),
    Relay(u32),
    Data(u32),
    Set(crate::host_device::HostDevice),
    Force(ladder_runtime::BitArea, u32),
    Unforce(ladder_runtime::BitArea, u32),
}

/// The host writes waiting for the next scan, in order. A write of what a
/// waiting write writes (the same key) replaces it: between two scans only
/// the last value of a device reaches the program, and writes that partly
/// overlap keep their order, so the image after them is the same. So the
/// queue holds at most one write per device, and at most `limit` of them
/// (a client that writes faster than the PLC scans, or while it is
/// paused, gets "busy" rather than memory without end).
struct Pending {
    writes: Vec<Option<HostWrite>>,
    at: std::collections::HashMap<WriteKey, usize>,
    limit: usize,
}

impl Pending {
    fn new(limit: usize) -> Pending {
        Pending {
            writes: Vec::new(),
            at: std::collections::HashMap::new(),
            limit,
        }
    }

    /// Queues all of `writes`, or none when they would leave more than
    /// `limit` writes waiting.
    fn push(&mut self, writes: &[HostWrite]) -> bool {
        let new: std::collections::HashSet<WriteKey> = writes
            .iter()
            .map(|w| w.key())
            .filter(|key| !self.at.contains_key(key))
            .collect();
        if self.at.len() + new.len() > self.limit {
            return false;
        }
        for &write in writes {
            if let Some(earlier) = self.at.insert(write.key(), self.writes.len()) {
                self.writes[earlier] = None;
            }
            self.writes.push(Some(write));
        }
        // Replaced writes leave holes; closed up when they are the most, so
        // that a client writing one device while the PLC is paused does not
        // grow the queue.
        if self.writes.len() > 2 * self.at.len() + 64 {
            self.writes.retain(Option::is_some);
            for (position, write) in self.writes.iter().enumerate() {
                if let Some(write) = write {
                    self.at.insert(write.key(), position);
                }
            }
        }
        true
    }

    fn take(&mut self) -> Vec<HostWrite> {
        self.at.clear();
        std::mem::take(&mut self.writes).into_iter().flatten().collect()
    }
}

/// How many host writes (devices) may wait for the next scan by default.
pub const DEFAULT_QUEUED_WRITES: usize = 65_536;

/// Wake-up latencies the statistics keep for their percentiles: the
/// latest minute at a 10 ms period.
pub const JITTER_WINDOW: usize = 6000;

/// Scan timing since the start (or the latest reset).
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
    /// The sum of every scan's wake-up latency (for the average).
    pub jitter_total: Duration,
}

/// The wake-up latencies of the latest scans, for p50/p99.
#[derive(Default)]
pub struct JitterWindow {
    latencies: VecDeque<Duration>,
}

/// Percentiles of the window: p50, p99 and max.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Percentiles {
    pub samples: usize,
    pub p50: Duration,
    pub p99: Duration,
    pub max: Duration,
}

impl JitterWindow {
    pub fn push(&mut self, latency: Duration) {
        if self.latencies.len() >= JITTER_WINDOW {
            self.latencies.pop_front();
        }
        self.latencies.push_back(latency);
    }

    pub fn percentiles(&self) -> Percentiles {
        let mut sorted: Vec<Duration> = self.latencies.iter().copied().collect();
        sorted.sort_unstable();
        let at = |fraction: f64| {
            // Nearest rank: the smallest value with `fraction` of them at or below it.
            let rank = ((fraction * sorted.len() as f64).ceil() as usize).clamp(1, sorted.len());
            sorted[rank - 1]
        };
        if sorted.is_empty() {
            return Percentiles::default();
        }
        Percentiles {
            samples: sorted.len(),
            p50: at(0.50),
            p99: at(0.99),
            max: sorted[sorted.len() - 1],
        }
    }
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
    /// The latest published image. The lock is held only to swap or clone
    /// the pointer: a reader that takes its time (a JSON reply for 256
    /// devices, an OPC UA sample) holds its own copy, never the scan.
    image: Mutex<Arc<Memory>>,
    /// The image published before, reused for the next publish when no
    /// reader holds it any more (no allocation per scan).
    spare: Mutex<Option<Arc<Memory>>>,
    /// A program waiting to replace the running one between two scans.
    pending: Mutex<Option<super::change::Loaded>>,
    /// Programs swapped in so far.
    swaps: std::sync::atomic::AtomicU64,
    writes: Mutex<Pending>,
    stats: Mutex<Stats>,
    stop: AtomicBool,
    control: Mutex<Control>,
    view: Mutex<Option<Arc<LadderView>>>,
    identity: Mutex<Option<Arc<super::change::Identity>>>,
    recorders: Mutex<Vec<Weak<Recorder>>>,
    /// How many recorders (event streams) may exist at once.
    most_recorders: std::sync::atomic::AtomicUsize,
    started: Instant,
    /// Some scan has published its image.
    published: AtomicBool,
    /// Bumped (and the condition signalled) when the scan thread should
    /// look again at once: a stop, a program offered, a control change.
    wake: Mutex<u64>,
    woken: Condvar,
    jitter: Mutex<JitterWindow>,
}

impl Default for Shared {
    fn default() -> Self {
        Shared {
            image: Mutex::new(Arc::from(Memory::new_boxed())),
            spare: Mutex::new(None),
            pending: Mutex::new(None),
            swaps: std::sync::atomic::AtomicU64::new(0),
            writes: Mutex::new(Pending::new(DEFAULT_QUEUED_WRITES)),
            stats: Mutex::new(Stats::default()),
            stop: AtomicBool::new(false),
            control: Mutex::new(Control::default()),
            view: Mutex::new(None),
            identity: Mutex::new(None),
            recorders: Mutex::new(Vec::new()),
            most_recorders: std::sync::atomic::AtomicUsize::new(MOST_EVENT_STREAMS),
            started: Instant::now(),
            published: AtomicBool::new(false),
            wake: Mutex::new(0),
            woken: Condvar::new(),
            jitter: Mutex::new(JitterWindow::default()),
        }
    }
}

/// Copies an image byte for byte, heap to heap (a `*a = *b` of 138 KB may
/// pass through the stack in a debug build).
fn copy_image(target: &mut Memory, source: &Memory) {
    bytemuck::bytes_of_mut(target).copy_from_slice(bytemuck::bytes_of(source));
}

fn heap_copy(source: &Memory) -> Arc<Memory> {
    let mut copy = Memory::new_boxed();
    copy_image(&mut copy, source);
    Arc::from(copy)
}

/// A lock whose holder panicked is still usable: the data is plain values.
fn lock<T>(mutex: &Mutex<T>) -> MutexGuard<'_, T> {
    mutex.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
}

impl Shared {
    /// The image as the latest scan left it.
    pub fn image(&self) -> Arc<Memory> {
        Arc::clone(&lock(&self.image))
    }

    pub fn publish(&self, image: &Memory) {
        let spare = lock(&self.spare).take();
        let mut next = match spare {
            Some(mut spare) => match Arc::get_mut(&mut spare) {
                Some(memory) => {
                    copy_image(memory, image);
                    spare
                }
                None => heap_copy(image),
            },
            None => heap_copy(image),
        };
        std::mem::swap(&mut *lock(&self.image), &mut next);
        *lock(&self.spare) = Some(next);
        self.published.store(true, Ordering::Release);
    }

    /// Whether any image was published yet.
    pub fn published(&self) -> bool {
        self.published.load(Ordering::Acquire)
    }

    /// Queues host writes for the next scan; false (none queued) when
    /// the queue is full (`Pending`): the client is told the PLC is busy.
    #[must_use]
    pub fn queue(&self, writes: Vec<HostWrite>) -> bool {
        lock(&self.writes).push(&writes)
    }

    /// How many devices may wait for the next scan (`--max-queued-writes`).
    pub fn limit_writes(&self, limit: usize) {
        lock(&self.writes).limit = limit.max(1);
    }

    pub fn take_writes(&self) -> Vec<HostWrite> {
        lock(&self.writes).take()
    }

    pub fn stats(&self) -> Stats {
        *lock(&self.stats)
    }

    pub fn update_stats(&self, update: impl FnOnce(&mut Stats)) {
        update(&mut lock(&self.stats));
    }

    /// Counts one scan's wake-up latency in the window.
    pub fn record_latency(&self, latency: Duration) {
        lock(&self.jitter).push(latency);
    }

    pub fn jitter_percentiles(&self) -> Percentiles {
        lock(&self.jitter).percentiles()
    }

    /// Starts the statistics and the window afresh.
    pub fn reset_stats(&self) {
        *lock(&self.stats) = Stats::default();
        *lock(&self.jitter) = JitterWindow::default();
    }

    /// The wake-up generation: pass it to `sleep_until`.
    pub fn generation(&self) -> u64 {
        *lock(&self.wake)
    }

    /// Tells the scan thread (and the retain thread) to look again now.
    pub fn wake(&self) {
        *lock(&self.wake) += 1;
        self.woken.notify_all();
    }

    /// Sleeps until `deadline`, or until woken after `generation` was read
    /// (a wake between reading it and sleeping is not lost).
    pub fn sleep_until(&self, deadline: Instant, generation: u64) {
        let mut current = lock(&self.wake);
        while *current == generation {
            let now = Instant::now();
            if now >= deadline {
                return;
            }
            current = match self.woken.wait_timeout(current, deadline - now) {
                Ok((guard, _)) => guard,
                Err(poisoned) => poisoned.into_inner().0,
            };
        }
    }

    /// Sleeps until `deadline` or a stop; true when stopping.
    pub fn wait_stop_until(&self, deadline: Instant) -> bool {
        loop {
            let generation = self.generation();
            if self.stopping() || Instant::now() >= deadline {
                return self.stopping();
            }
            self.sleep_until(deadline, generation);
        }
    }

    /// Hands a compiled program to the scan thread; false (and nothing
    /// changes) while another one is still waiting to be swapped in.
    pub fn offer(&self, program: super::change::Loaded) -> bool {
        let mut pending = lock(&self.pending);
        if pending.is_some() {
            return false;
        }
        *pending = Some(program);
        drop(pending);
        self.wake();
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

    pub fn control(&self) -> MutexGuard<'_, Control> {
        lock(&self.control)
    }

    /// The drawing of the running program.
    pub fn view(&self) -> Option<Arc<LadderView>> {
        lock(&self.view).clone()
    }

    pub fn set_view(&self, view: Arc<LadderView>) {
        *lock(&self.view) = Some(view);
    }

    /// The running program's identity.
    pub fn identity(&self) -> Option<Arc<super::change::Identity>> {
        lock(&self.identity).clone()
    }

    pub fn set_identity(&self, identity: Arc<super::change::Identity>) {
        *lock(&self.identity) = Some(identity);
    }

    /// A recorder of `devices` after every scan from now on, until the
    /// returned handle is dropped (or its client stops taking samples);
    /// `None` when `--max-event-streams` recorders exist already.
    pub fn record(&self, devices: Vec<HostDevice>) -> Option<Arc<Recorder>> {
        let per_sample = size_of::<Sample>() + 4 * devices.len();
        let recorder = Arc::new(Recorder {
            devices,
            samples: Mutex::new(VecDeque::new()),
            capacity: (RECORDER_BYTES / per_sample).max(16),
            lost: std::sync::atomic::AtomicU64::new(0),
            taken: Mutex::new(Instant::now()),
            dropped: AtomicBool::new(false),
        });
        let mut recorders = lock(&self.recorders);
        recorders.retain(|r| r.strong_count() > 0);
        if recorders.len() >= self.most_recorders.load(Ordering::Relaxed) {
            return None;
        }
        recorders.push(Arc::downgrade(&recorder));
        Some(recorder)
    }

    /// How many event streams may be served at once (`--max-event-streams`).
    pub fn limit_recorders(&self, most: usize) {
        self.most_recorders.store(most.max(1), Ordering::Relaxed);
    }

    /// Appends the values `image` holds after a scan to every recorder; a
    /// recorder whose client took nothing for `RECORDER_STALL` is dropped.
    pub fn sample(&self, image: &Memory) {
        let time_ms = self.started.elapsed().as_millis() as u64;
        let mut recorders = lock(&self.recorders);
        recorders.retain(|weak| match weak.upgrade() {
            Some(recorder) if lock(&recorder.taken).elapsed() >= RECORDER_STALL => {
                recorder.dropped.store(true, Ordering::Relaxed);
                *lock(&recorder.samples) = VecDeque::new();
                false
            }
            Some(_) => true,
            None => false,
        });
        for recorder in recorders.iter().filter_map(Weak::upgrade) {
            let values = recorder
                .devices
                .iter()
                .map(|d| image.read_device(d.device, d.width).unwrap_or(0))
                .collect();
            let mut samples = lock(&recorder.samples);
            if samples.len() >= recorder.capacity {
                samples.pop_front();
                recorder.lost.fetch_add(1, Ordering::Relaxed);
            }
            samples.push_back(Sample {
                scan: u64::from(image.scan_count),
                time_ms,
                values,
            });
        }
    }

    pub fn stop(&self) {
        self.stop.store(true, Ordering::Relaxed);
        self.wake();
    }

    pub fn stopping(&self) -> bool {
        self.stop.load(Ordering::Relaxed)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn waiting_writes_of_one_device_keep_the_last_and_the_queue_is_bounded() {
        let mut pending = Pending::new(3);
        assert!(pending.push(&[HostWrite::Data(0, 1), HostWrite::Data(1, 1)]));
        assert!(pending.push(&[HostWrite::Data(0, 2), HostWrite::Input(3, true)]));
        assert!(!pending.push(&[HostWrite::Data(2, 7)]), "a fourth device is refused");
        assert!(pending.push(&[HostWrite::Data(1, 5)]), "a waiting device is replaced");
        assert_eq!(
            pending.take(),
            [HostWrite::Data(0, 2), HostWrite::Input(3, true), HostWrite::Data(1, 5)]
        );
        assert!(pending.push(&[HostWrite::Data(2, 7)]), "empty again after a scan");
        for value in 0..100_000 {
            assert!(pending.push(&[HostWrite::Data(9, (value % 30_000) as i16)]));
        }
        assert!(
            pending.writes.len() <= 2 * pending.at.len() + 65,
            "{}",
            pending.writes.len()
        );
        assert_eq!(pending.take(), [HostWrite::Data(2, 7), HostWrite::Data(9, 9_999)]);
    }
}
