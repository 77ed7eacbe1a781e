//! What the scan thread and the servers share: the image as the latest scan
//! left it (servers read this copy, never the live image), the host writes
//! waiting to be applied (and the writers waiting for them: `acks`), the scan statistics, the RUN/STOP switch and
//! breakpoints, the drawing of the running program, the recorders of the
//! trend, the remote I/O's exchange, and the stop flag.

use super::acks::{Acks, NotApplied, Ticket};
use super::control::Control;
use super::scan_lock::{lock, ScanGuard, ScanLock};
use super::view::LadderView;
use ladder_front::host_device::HostDevice;
use ladder_runtime::Memory;
use std::collections::VecDeque;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Condvar, Mutex, Weak};
use std::time::{Duration, Instant};

/// Bytes of samples a recorder keeps for its client at most (older ones
/// are lost and counted): at a 10 ms period and 256 watched devices, about
/// two and a half seconds, twenty-five times the push period.
const RECORDER_BYTES: usize = 1 << 20;
/// Images kept for publishing (the latest, and those readers may hold).
const POOLED_IMAGES: usize = 4;
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
    samples: ScanLock<Ring>,
    lost: std::sync::atomic::AtomicU64,
    /// When the client last took its samples.
    taken: ScanLock<Instant>,
    /// Dropped for not taking them (`RECORDER_STALL`).
    dropped: AtomicBool,
}

/// A recorder's samples, in storage allocated once when the stream opens:
/// the scan thread never allocates or frees for a trend (an allocator lock
/// held by a server thread that the scheduler put aside cost a realtime
/// scan several milliseconds under load).
struct Ring {
    /// Scan number and time of each sample kept (`RECORDER_BYTES` of them).
    heads: VecDeque<(u64, u64)>,
    /// Their values, one row of `devices.len()` per sample.
    values: VecDeque<i32>,
    capacity: usize,
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
        let width = self.devices.len();
        let mut ring = lock(&self.samples);
        let Ring { heads, values, .. } = &mut *ring;
        let samples = heads
            .drain(..)
            .map(|(scan, time_ms)| Sample {
                scan,
                time_ms,
                values: values.drain(..width).collect(),
            })
            .collect();
        (samples, self.lost.swap(0, Ordering::Relaxed))
    }

    /// Whether the client was dropped for not reading (its stream ends).
    pub fn dropped(&self) -> bool {
        self.dropped.load(Ordering::Relaxed)
    }
}

/// A write from a client, applied as a host write at the end of the scan
/// in progress (or at once when none is), before the next scan.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HostWrite {
    /// Xn of the input image.
    Input(u32, bool),
    Output(u32, bool),
    Relay(u32, bool),
    Data(u32, i16),
    /// Any device, as `ladderc run --set` writes it.
    Set(ladder_front::host_device::HostDevice, i32),
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
    Set(ladder_front::host_device::HostDevice),
    Force(ladder_runtime::BitArea, u32),
    Unforce(ladder_runtime::BitArea, u32),
}

/// The host writes waiting to be applied, in order. A write of what a
/// waiting write writes (the same key) replaces it: in one batch only the
/// last value of a device reaches the program, and writes that partly
/// overlap keep their order, so the image after them is the same. So the
/// queue holds at most one write per device, and at most `limit` of them
/// (clients that together write more devices during one scan get "busy"
/// rather than memory without end).
struct Pending {
    writes: Vec<Option<HostWrite>>,
    at: std::collections::HashMap<WriteKey, usize>,
    limit: usize,
    /// Batches taken so far: a write queued now is in batch `taken + 1`.
    taken: u64,
}

impl Pending {
    fn new(limit: usize) -> Pending {
        Pending {
            writes: Vec::new(),
            at: std::collections::HashMap::new(),
            limit,
            taken: 0,
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
        self.taken += 1;
        self.at.clear();
        std::mem::take(&mut self.writes).into_iter().flatten().collect()
    }
}

/// How many host writes (devices) may wait to be applied by default.
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
    image: ScanLock<Arc<Memory>>,
    /// Every image published lately, kept for reuse: a publish copies into
    /// one no reader holds any more, so the scan thread neither allocates
    /// nor frees 138 KB per scan (both take the process's memory-map lock
    /// and stalled a realtime scan while pollers held copies).
    pool: ScanLock<Vec<Arc<Memory>>>,
    /// A program waiting to replace the running one between two scans.
    pending: ScanLock<Option<super::change::Loaded>>,
    /// Programs swapped in so far.
    swaps: std::sync::atomic::AtomicU64,
    writes: ScanLock<Pending>,
    /// Some write waits in `writes` (read by the scan thread while it
    /// waits for its next scan, without taking the lock).
    writes_waiting: AtomicBool,
    /// The batches of writes applied, and the writers waiting for theirs.
    acks: Acks,
    stats: ScanLock<Stats>,
    stop: AtomicBool,
    control: ScanLock<Control>,
    view: ScanLock<Option<Arc<LadderView>>>,
    identity: ScanLock<Option<Arc<super::change::Identity>>>,
    recorders: ScanLock<Vec<Weak<Recorder>>>,
    /// How many recorders (event streams) may exist at once.
    most_recorders: std::sync::atomic::AtomicUsize,
    started: Instant,
    /// Some scan has published its image.
    published: AtomicBool,
    /// Bumped (and the condition signalled) when the scan thread should
    /// look again at once: a stop, a program offered, a control change.
    wake: Mutex<u64>,
    woken: Condvar,
    jitter: ScanLock<JitterWindow>,
    /// The remote I/O's pollers and their inputs and outputs (`--io`).
    remote_io: std::sync::OnceLock<Arc<super::remote_io::Exchange>>,
}

impl Default for Shared {
    fn default() -> Self {
        Shared {
            image: super::scan_lock::new(Arc::from(Memory::new_boxed())),
            pool: super::scan_lock::new(Vec::with_capacity(POOLED_IMAGES)),
            pending: super::scan_lock::new(None),
            swaps: std::sync::atomic::AtomicU64::new(0),
            writes: super::scan_lock::new(Pending::new(DEFAULT_QUEUED_WRITES)),
            writes_waiting: AtomicBool::new(false),
            acks: Acks::default(),
            stats: super::scan_lock::new(Stats::default()),
            stop: AtomicBool::new(false),
            control: super::scan_lock::new(Control::default()),
            view: super::scan_lock::new(None),
            identity: super::scan_lock::new(None),
            recorders: super::scan_lock::new(Vec::new()),
            most_recorders: std::sync::atomic::AtomicUsize::new(MOST_EVENT_STREAMS),
            started: Instant::now(),
            published: AtomicBool::new(false),
            wake: Mutex::new(0),
            woken: Condvar::new(),
            jitter: super::scan_lock::new(JitterWindow::default()),
            remote_io: std::sync::OnceLock::new(),
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

/// The lock the scan thread sleeps on (a condition variable's, so the
/// standard library's); its holder panicking leaves plain values.
fn lock_wake(mutex: &Mutex<u64>) -> std::sync::MutexGuard<'_, u64> {
    mutex.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
}

impl Shared {
    /// The image as the latest scan left it.
    pub fn image(&self) -> Arc<Memory> {
        Arc::clone(&lock(&self.image))
    }

    pub fn publish(&self, image: &Memory) {
        let mut pool = lock(&self.pool);
        // Held by the pool alone: no reader, no published slot.
        let free = pool.iter_mut().find(|pooled| Arc::strong_count(pooled) == 1);
        let next = match free {
            Some(pooled) => {
                if let Some(memory) = Arc::get_mut(pooled) {
                    copy_image(memory, image);
                }
                Arc::clone(pooled)
            }
            None => {
                // Every pooled image is still read (or the pool is new).
                let copy = heap_copy(image);
                if pool.len() < POOLED_IMAGES {
                    pool.push(Arc::clone(&copy));
                }
                copy
            }
        };
        drop(pool);
        *lock(&self.image) = next;
        self.published.store(true, Ordering::Release);
    }

    /// Whether any image was published yet.
    pub fn published(&self) -> bool {
        self.published.load(Ordering::Acquire)
    }

    /// Queues host writes: the scan thread applies them at the end of the
    /// scan in progress, or at once when none is running (it is woken).
    /// `None` (none queued) when the queue is full (`Pending`): the client
    /// is told the PLC is busy. Answer the client once the ticket is
    /// applied (`wait_applied`).
    #[must_use]
    pub fn queue(&self, writes: Vec<HostWrite>) -> Option<Ticket> {
        let mut pending = lock(&self.writes);
        if !pending.push(&writes) {
            return None;
        }
        let ticket = Ticket(pending.taken + 1);
        self.writes_waiting.store(true, Ordering::Release);
        drop(pending);
        self.wake();
        Some(ticket)
    }

    /// How many devices may wait to be applied (`--max-queued-writes`).
    pub fn limit_writes(&self, limit: usize) {
        lock(&self.writes).limit = limit.max(1);
    }

    /// The writes queued since the last call, in order: a batch, to be
    /// marked `acknowledge`d once applied and published.
    pub fn take_writes(&self) -> Vec<HostWrite> {
        let mut pending = lock(&self.writes);
        self.writes_waiting.store(false, Ordering::Release);
        pending.take()
    }

    /// Whether writes wait to be taken.
    pub fn writes_waiting(&self) -> bool {
        self.writes_waiting.load(Ordering::Acquire)
    }

    /// Every batch taken so far is applied and the published image shows
    /// it: their writers are answered. Called by the scan thread alone
    /// (which alone takes batches).
    pub fn acknowledge(&self) {
        let taken = lock(&self.writes).taken;
        self.acks.applied(taken);
    }

    /// Blocks until the write of `ticket` is applied (bounded: `acks`).
    pub fn wait_applied(&self, ticket: Ticket) -> Result<(), NotApplied> {
        self.acks.wait(ticket)
    }

    /// Waits as a task until the write of `ticket` is applied.
    pub async fn applied(&self, ticket: Ticket) -> Result<(), NotApplied> {
        self.acks.wait_async(ticket).await
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

    /// The remote I/O, once started (`--io`).
    pub fn remote_io(&self) -> Option<&super::remote_io::Exchange> {
        self.remote_io.get().map(|exchange| &**exchange)
    }

    /// Hands the scan thread the remote I/O (once, before the first scan).
    pub fn set_remote_io(&self, exchange: Arc<super::remote_io::Exchange>) {
        let _ = self.remote_io.set(exchange);
    }

    /// The wake-up generation: pass it to `sleep_until`.
    pub fn generation(&self) -> u64 {
        *lock_wake(&self.wake)
    }

    /// Tells the scan thread (and the retain thread) to look again now.
    pub fn wake(&self) {
        *lock_wake(&self.wake) += 1;
        self.woken.notify_all();
    }

    /// Sleeps until `deadline`, or until woken after `generation` was read
    /// (a wake between reading it and sleeping is not lost).
    pub fn sleep_until(&self, deadline: Instant, generation: u64) {
        let mut current = lock_wake(&self.wake);
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

    pub fn control(&self) -> ScanGuard<'_, Control> {
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
        let per_sample = size_of::<(u64, u64)>() + 4 * devices.len();
        let capacity = (RECORDER_BYTES / per_sample).max(16);
        let recorder = Arc::new(Recorder {
            samples: super::scan_lock::new(Ring {
                heads: VecDeque::with_capacity(capacity),
                values: VecDeque::with_capacity(capacity * devices.len()),
                capacity,
            }),
            devices,
            lost: std::sync::atomic::AtomicU64::new(0),
            taken: super::scan_lock::new(Instant::now()),
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
                // Its storage is freed with the stream (the connection
                // closes for the stalled write soon after), not here.
                recorder.dropped.store(true, Ordering::Relaxed);
                false
            }
            Some(_) => true,
            None => false,
        });
        let scan = u64::from(image.scan_count);
        for recorder in recorders.iter().filter_map(Weak::upgrade) {
            let mut ring = lock(&recorder.samples);
            if ring.heads.len() >= ring.capacity {
                ring.heads.pop_front();
                ring.values.drain(..recorder.devices.len());
                recorder.lost.fetch_add(1, Ordering::Relaxed);
            }
            ring.heads.push_back((scan, time_ms));
            let values = recorder
                .devices
                .iter()
                .map(|d| image.read_device(d.device, d.width).unwrap_or(0));
            ring.values.extend(values);
        }
    }

    pub fn stop(&self) {
        self.stop.store(true, Ordering::Relaxed);
        self.acks.stop();
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

    fn d(n: u32) -> HostDevice {
        HostDevice {
            device: ladder_runtime::Device::Word(ladder_runtime::WordArea::D, n),
            width: ladder_runtime::Width::Single,
        }
    }

    #[test]
    fn a_recorder_keeps_its_newest_samples_in_order_and_counts_the_lost() {
        let shared = Shared::default();
        let recorder = shared.record(vec![d(0), d(1)]).unwrap();
        let capacity = lock(&recorder.samples).capacity;
        let mut image = Memory::new_boxed();
        for scan in 0..capacity as i32 + 5 {
            image.scan_count = scan as u32;
            image.write_device(d(0).device, d(0).width, scan % 10_000);
            image.write_device(d(1).device, d(1).width, -(scan % 10_000));
            shared.sample(&image);
        }
        let (samples, lost) = recorder.take();
        assert_eq!((samples.len(), lost), (capacity, 5));
        for (n, sample) in samples.iter().enumerate() {
            let scan = n as i32 + 5;
            let value = scan % 10_000;
            assert_eq!((sample.scan, &sample.values[..]), (scan as u64, &[value, -value][..]));
        }
        assert_eq!(recorder.take(), (Vec::new(), 0), "taken once");
        let ring = lock(&recorder.samples);
        assert!(ring.heads.capacity() >= capacity && ring.values.capacity() >= 2 * capacity);
    }

    #[test]
    fn publishing_reuses_images_no_reader_holds() {
        let shared = Shared::default();
        let mut image = Memory::new_boxed();
        let mut held = Vec::new();
        for value in 0..20 {
            image.write_device(d(7).device, d(7).width, value);
            shared.publish(&image);
            let published = shared.image();
            assert_eq!(published.read_device(d(7).device, d(7).width), Some(value));
            // A slow reader keeps a copy for a while; earlier copies stay
            // as they were read.
            held.push(published);
            if held.len() > 2 {
                held.remove(0);
            }
            for (age, copy) in held.iter().rev().enumerate() {
                assert_eq!(copy.read_device(d(7).device, d(7).width), Some(value - age as i32));
            }
        }
        assert!(lock(&shared.pool).len() <= POOLED_IMAGES);
    }
}
