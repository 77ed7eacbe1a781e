//! The scan thread: it owns the engine (compiled code need not be sent
//! between threads), scans at a fixed period with the real elapsed time (so
//! timers run in real time), publishes the image after every scan, applies
//! the queued host writes as a CPU's END processing does (at the end of the
//! scan in progress, or at once while it waits for the next scan, is
//! stopped or paused) and publishes them before their writers are
//! answered, follows the RUN/STOP switch and the debugger, and swaps in a
//! program offered for online change between two scans.

use super::change;
use super::retain;
use super::shared::{HostWrite, Shared};
use super::{announce, realtime};
use ladder_engine::{instantiate, Engine, EngineKind};
use ladder_front::host_device::HostDevice;
use ladder_runtime::{BitArea, Device, Width, WordArea};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// When the next scan is due, and the time to report to it.
struct Clock {
    period: Duration,
    due: Instant,
    previous: Instant,
    carried: Duration,
    /// With `--realtime`: how long before the due time the sleep ends; the
    /// rest is spun, so the scan starts when due and not when the OS's
    /// timer gets round to it (a few percent of one core).
    spin: Duration,
}

/// How the scan thread runs.
pub struct Setup {
    pub kind: EngineKind,
    pub period: Duration,
    /// SCHED_FIFO, locked memory and a spun end of each wait (`--realtime`).
    pub realtime: bool,
    /// What the retain file restored: the first scan starts with it.
    pub restored: Vec<(retain::LatchRange, Vec<i32>)>,
    /// The latched devices, which STOP→RUN does not clear.
    pub latched: Vec<retain::LatchRange>,
}

/// Starts the scan thread and waits until its engine is ready for the
/// first scan; `Err` is a message when it cannot run the program.
pub fn start(first: change::Loaded, setup: Setup, shared: &Arc<Shared>) -> Result<JoinHandle<()>, String> {
    let (ready, started) = std::sync::mpsc::channel();
    let scanner = {
        let shared = Arc::clone(shared);
        std::thread::spawn(move || {
            let _stop = StopOnExit(Arc::clone(&shared));
            for line in realtime::prepare_scan_thread(setup.realtime) {
                announce(&line);
            }
            scan_loop(
                first,
                setup.kind,
                (setup.period, setup.realtime),
                (&setup.restored, &setup.latched),
                &shared,
                &ready,
            )
        })
    };
    started
        .recv()
        .map_err(|_| "the scan thread ended before it started".to_string())??;
    Ok(scanner)
}

/// Stops the server when the scan thread ends, however it ends: after a
/// panic (in the engine, in a write) the writers waiting for their batch
/// are told at once and the servers stop, rather than waiting out their
/// time and then serving an image no scan updates any more.
struct StopOnExit(Arc<Shared>);

impl Drop for StopOnExit {
    fn drop(&mut self) {
        self.0.stop();
    }
}

/// The scan thread: the engine lives here (compiled code need not be sent
/// between threads). Between two scans it swaps in a new program when one
/// is offered, keeping the image (see `change`); the scan count and the
/// clock go on.
fn scan_loop(
    first: change::Loaded,
    kind: EngineKind,
    (period, realtime): (Duration, bool),
    (restored, latched): (&[(retain::LatchRange, Vec<i32>)], &[retain::LatchRange]),
    shared: &Shared,
    ready: &std::sync::mpsc::Sender<Result<(), String>>,
) {
    let start = Instant::now();
    let mut clock = Clock {
        period,
        due: start,
        previous: start,
        carried: Duration::ZERO,
        spin: if realtime {
            realtime::SPIN.min(period / 10)
        } else {
            Duration::ZERO
        },
    };
    let mut loaded = first;
    let mut image: Option<Box<ladder_runtime::Memory>> = None;
    let mut started = false;
    loop {
        let (next, last_image) = {
            let native = loaded.native.take().filter(|_| kind == EngineKind::Jit);
            let built = match native {
                Some(native) => Ok(Box::new(ladder_engine::InProcess::new(native)) as Box<dyn Engine>),
                None => instantiate(kind, &loaded.program, &[]),
            };
            let mut engine = match built {
                Ok(engine) => engine,
                Err(error) => {
                    if !started {
                        let _ = ready.send(Err(format!("{error:?}")));
                    }
                    shared.stop();
                    return;
                }
            };
            if let Some(image) = image.take() {
                engine.load_image(&image);
            } else if !restored.is_empty() {
                // Power on with the battery-backed devices as they were.
                if let Some(first) = engine.image() {
                    let mut first = Box::new(*first);
                    retain::apply(&mut first, restored);
                    engine.load_image(&first);
                    shared.publish(&first);
                }
            }
            shared.set_view(std::sync::Arc::clone(&loaded.view));
            shared.set_identity(std::sync::Arc::clone(&loaded.identity));
            if shared.swaps() > 0 || engine.image().is_some_and(|m| m.scan_count > 0) {
                // Every online change in the log: which program, from when.
                let identity = &loaded.identity;
                announce(&format!(
                    "online change: {} (sha256 {}) loaded {}, running from scan {}",
                    identity.name,
                    identity.sha256,
                    identity.loaded_at_text(),
                    engine.image().map_or(0, |m| m.scan_count) + 1
                ));
            }
            if !started {
                started = true;
                let _ = ready.send(Ok(()));
            }
            let next = run(engine.as_mut(), &mut clock, shared, latched);
            (next, engine.image().map(|m| Box::new(*m)))
        };
        let (Some(next), Some(last_image)) = (next, last_image) else {
            return;
        };
        image = Some(change::carry_over(&last_image, &loaded, &next));
        loaded = next;
        shared.swapped();
    }
}

/// What the scan thread does when a scan is due, by the RUN/STOP switch
/// and the debugger.
enum Due {
    /// A scan reporting the elapsed time (running) or the period (a step).
    Scan { step: bool },
    /// STOP: writes apply, no scan; `entering` turns every Y OFF.
    Stopped { entering: bool },
    /// Paused: no scan until a step (writes apply at once all the same).
    Paused,
}

/// Scans until stopped (None) or offered a new program (between two scans).
fn run(
    engine: &mut dyn Engine,
    clock: &mut Clock,
    shared: &Shared,
    latched: &[retain::LatchRange],
) -> Option<change::Loaded> {
    let mut was_stopped = false;
    while !shared.stopping() {
        match wait_until_due(clock, shared) {
            Woken::Due => {}
            Woken::Writes => {
                // Between two scans (or stopped, or paused): applied now,
                // as END processing applies a request that comes while the
                // CPU waits out its constant scan; the program sees them
                // at its next scan, as before. The remote outputs follow
                // at once (a Y written in STOP reaches its coil).
                end_processing(engine, shared, Outputs::Refresh);
                continue;
            }
            Woken::Stop => return None,
            Woken::Program(next) => return Some(*next),
        }
        let due = decide(shared, was_stopped);
        let began = Instant::now();
        match due {
            Due::Stopped { entering } => {
                was_stopped = true;
                if entering {
                    all_outputs_off(engine);
                }
                // The I/O refresh of a CPU in STOP: the remote inputs,
                // status relays and error counts into the image, the
                // writes applied, then the outputs to the modules.
                refresh_inputs(engine, shared);
                end_processing(engine, shared, Outputs::Refresh);
                idle(clock, began);
            }
            // Writes while paused wake the thread and apply at once
            // (`Woken::Writes`); a due time passes without a scan, but
            // with the I/O refreshed as in STOP.
            Due::Paused => {
                refresh_inputs(engine, shared);
                end_processing(engine, shared, Outputs::Refresh);
                idle(clock, began);
            }
            Due::Scan { step } => {
                // STOP→RUN as an FX does it: the non-latched devices
                // cleared, and the first scan the first again (M8002).
                if was_stopped {
                    if let Some(image) = engine.image() {
                        let fresh = retain::restart(image, latched);
                        engine.load_image(&fresh);
                    }
                }
                was_stopped = false;
                if !scan(engine, clock, shared, began, step) {
                    shared.stop();
                    break;
                }
            }
        }
    }
    None
}

/// Why the wait for the next scan ended.
enum Woken {
    /// The scan is due (or a step waits).
    Due,
    /// Host writes wait, and no scan is due yet (nor spun for).
    Writes,
    /// The server stops.
    Stop,
    /// A program was offered for online change (boxed: it is large, and
    /// comes once per change).
    Program(Box<change::Loaded>),
}

/// Sleeps until the absolute deadline of the next scan; a stop, a program
/// offered, a control change or a host write wakes it at once.
fn wait_until_due(clock: &Clock, shared: &Shared) -> Woken {
    loop {
        let generation = shared.generation();
        if shared.stopping() {
            return Woken::Stop;
        }
        if let Some(next) = shared.take_program() {
            return Woken::Program(Box::new(next));
        }
        let now = Instant::now();
        if now >= clock.due || shared.control().step_waiting() {
            return Woken::Due;
        }
        let wake = clock.due.checked_sub(clock.spin).unwrap_or(clock.due);
        // Not in the spin before a due scan (`--realtime`): applying and
        // publishing there would start the scan late; the scan takes those
        // writes as it starts and answers them at its end.
        if now < wake && shared.writes_waiting() {
            return Woken::Writes;
        }
        if now >= wake {
            std::hint::spin_loop();
            continue;
        }
        shared.sleep_until(wake, generation);
    }
}

/// What the switch and the debugger make of a due scan (a step taken
/// counts down here).
fn decide(shared: &Shared, was_stopped: bool) -> Due {
    let mut control = shared.control();
    if control.stopped {
        Due::Stopped { entering: !was_stopped }
    } else if control.paused && control.steps == 0 {
        Due::Paused
    } else {
        let step = control.paused;
        if step {
            control.steps -= 1;
        }
        Due::Scan { step }
    }
}

/// One scan that `began` now: the queued writes, the scan, the writes
/// queued during it (END processing), the published image, the next due
/// time and the statistics. False when the engine failed (the server
/// stops).
fn scan(engine: &mut dyn Engine, clock: &mut Clock, shared: &Shared, began: Instant, step: bool) -> bool {
    let late = began.saturating_duration_since(clock.due);
    let elapsed = if step {
        clock.carried = Duration::ZERO;
        clock.period
    } else {
        began - clock.previous + clock.carried
    };
    clock.previous = began;
    let elapsed_ms = elapsed.as_millis().min(u128::from(u32::MAX)) as u32;
    clock.carried = elapsed - Duration::from_millis(u64::from(elapsed_ms));
    for write in shared.take_writes() {
        apply(engine, write);
    }
    super::remote_io::before_scan(shared, engine);
    if engine.scan(elapsed_ms).is_err() {
        return false;
    }
    if let Some(image) = engine.image() {
        super::remote_io::after_scan(shared, image);
        shared.sample(image);
        shared.control().after_scan(image, u64::from(image.scan_count));
    }
    // The writes queued during the scan go out with the next scan's
    // outputs (the program's result first, as an FX's END does).
    end_processing(engine, shared, Outputs::Kept);
    let took = began.elapsed();
    clock.due += clock.period;
    let overrun = !step && Instant::now() > clock.due;
    if step {
        // Steps run back to back: the next scan is due a period after
        // this one, not a period for every step taken (a resume after
        // `step 1000` would wait 1000 periods).
        idle(clock, Instant::now());
    } else if overrun {
        // Behind: the next scan starts now, not in a burst.
        clock.due = Instant::now();
    }
    shared.update_stats(|stats| {
        stats.scans += 1;
        stats.last = took;
        stats.min = Some(stats.min.map_or(took, |min| min.min(took)));
        stats.max = stats.max.max(took);
        stats.total += took;
        stats.jitter = stats.jitter.max(late);
        stats.jitter_total += late;
        stats.overruns += u64::from(overrun);
    });
    if !step {
        shared.record_latency(late);
    }
    true
}

/// A period without a scan (stopped or paused): the next scan is due a
/// period later and reports one period, not the time it waited.
fn idle(clock: &mut Clock, now: Instant) {
    clock.due = now + clock.period;
    clock.previous = now + clock.period;
    clock.carried = Duration::ZERO;
}

/// The input refresh of a CPU in STOP (or paused): the remote inputs,
/// status relays and error counts written, and X takes its input image
/// (a client's write to X shows too) without a scan.
fn refresh_inputs(engine: &mut dyn Engine, shared: &Shared) {
    super::remote_io::before_scan(shared, engine);
    engine.refresh_inputs();
}

/// Whether END processing hands the outputs to the remote I/O.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Outputs {
    /// After a scan: the scan handed them already; the writes go out
    /// with the next scan's.
    Kept,
    /// Stopped, paused or between two scans: the image with the writes
    /// applied is what the modules get now.
    Refresh,
}

/// END processing of the host writes: those queued since the last batch
/// applied, the remote outputs refreshed (`outputs`), the image that shows
/// them published (servers read that copy), then their writers answered,
/// so a read after the answer sees the write.
fn end_processing(engine: &mut dyn Engine, shared: &Shared, outputs: Outputs) {
    for write in shared.take_writes() {
        apply(engine, write);
    }
    if let Some(image) = engine.image() {
        if outputs == Outputs::Refresh {
            super::remote_io::after_scan(shared, image);
        }
        shared.publish(image);
    }
    shared.acknowledge();
}

/// STOP: every output OFF, as an FX turns its outputs off in STOP.
fn all_outputs_off(engine: &mut dyn Engine) {
    for n in 0..BitArea::Y.count() {
        let _ = engine.write(
            HostDevice {
                device: Device::Bit(BitArea::Y, n),
                width: Width::Single,
            },
            0,
        );
    }
}

/// A client's write as a host write (the same call a firmware host makes).
fn apply(engine: &mut dyn Engine, write: HostWrite) {
    let bit = |area, index| HostDevice {
        device: Device::Bit(area, index),
        width: Width::Single,
    };
    let _ = match write {
        HostWrite::Input(n, on) => engine.write(bit(BitArea::X, n), i32::from(on)),
        HostWrite::Output(n, on) => engine.write(bit(BitArea::Y, n), i32::from(on)),
        HostWrite::Relay(n, on) => engine.write(bit(BitArea::M, n), i32::from(on)),
        HostWrite::Data(n, value) => engine.write(
            HostDevice {
                device: Device::Word(WordArea::D, n),
                width: Width::Single,
            },
            i32::from(value),
        ),
        HostWrite::Set(device, value) => engine.write(device, value),
        HostWrite::Force(area, index, on) => engine.force(area, index, on),
        HostWrite::Unforce(area, index) => engine.unforce(area, index),
    };
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::acks::NotApplied;

    fn clock(due_in: Duration, spin: Duration) -> Clock {
        let now = Instant::now();
        Clock {
            period: Duration::from_millis(100),
            due: now + due_in,
            previous: now,
            carried: Duration::ZERO,
            spin,
        }
    }

    #[test]
    fn writes_wake_the_thread_between_scans_but_not_in_the_spin_before_one() {
        let shared = Shared::default();
        let _ticket = shared.queue(vec![HostWrite::Data(0, 1)]);
        let waiting = clock(Duration::from_secs(5), Duration::from_millis(1));
        assert!(
            matches!(wait_until_due(&waiting, &shared), Woken::Writes),
            "applied at once while the thread waits for the next scan"
        );
        // Due in 20 ms, spun for the last second: the spin has begun.
        let spinning = clock(Duration::from_millis(20), Duration::from_secs(1));
        assert!(
            matches!(wait_until_due(&spinning, &shared), Woken::Due),
            "the scan starts when due, its writes taken as it starts"
        );
        assert!(Instant::now() >= spinning.due);
        assert!(shared.writes_waiting(), "left for the scan to take");
    }

    #[test]
    fn a_scan_thread_that_panics_stops_the_server_and_every_wait() {
        let shared = Arc::new(Shared::default());
        let ticket = shared.queue(vec![HostWrite::Data(0, 1)]);
        let thread = {
            let shared = Arc::clone(&shared);
            std::thread::spawn(move || {
                let _stop = StopOnExit(shared);
                std::panic::resume_unwind(Box::new("a scan failed"));
            })
        };
        assert!(thread.join().is_err(), "the thread panicked");
        assert!(shared.stopping(), "the server stops");
        assert_eq!(
            ticket.map(|ticket| shared.wait_applied(ticket)),
            Some(Err(NotApplied::Stopping)),
            "the writer is told at once"
        );
    }
}
