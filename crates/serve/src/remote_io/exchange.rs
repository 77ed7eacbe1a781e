//! The handoff between the remote I/O pollers and the scan thread. Per
//! device: the freshest complete input snapshot (a poller replaces it whole
//! after a poll, the scan thread copies it into the input image before a
//! scan), the outputs the latest scan produced (the scan thread replaces
//! them, a poller copies them out to write), and the device's state for the
//! monitor. Each lock is held for a copy of a few values, never across
//! network I/O, and is a priority-inheriting one (`scan_lock`); a change
//! of outputs wakes the poller through `wake.rs`, without a lock: the scan
//! thread never waits on the network. The scan thread's hand-offs also
//! beat a heartbeat (`Beat`): a poller writes keep-alives only while it
//! beats, so a stalled scan thread does not feed a module's watchdog.

use super::config::{Device, InputTable, OnLoss, OutputTable, Source};
use crate::scan_lock::{self, lock, ScanLock};
use ladder_engine::Engine;
use ladder_front::host_device::HostDevice;
use ladder_runtime::{BitArea, Device as Place, Memory, Width, WordArea};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// Scan periods without a hand-off of the outputs after which the scan
/// thread counts as stalled and keep-alives stop.
pub const STALLED_AFTER: u32 = 3;

/// Every device's slot, in the file's order.
pub struct Exchange {
    pub slots: Vec<Arc<Slot>>,
}

/// One device: its configuration, its inputs and outputs, and its state.
pub struct Slot {
    pub device: Device,
    inputs: ScanLock<Inputs>,
    outputs: ScanLock<Outputs>,
    /// Raised when a scan changed the outputs: the poller writes them now
    /// rather than at its next poll (one signal per link: the devices of a
    /// serial line share it and their poller).
    pub changed: Arc<super::wake::Signal>,
    state: Mutex<State>,
    pub beat: Arc<Beat>,
}

/// When the scan thread last handed the outputs over (a scan, or a due
/// time in STOP or paused), without a lock.
#[derive(Debug)]
pub struct Beat {
    epoch: Instant,
    /// Microseconds from `epoch` to the latest hand-off (0: none yet).
    last: AtomicU64,
    /// How long without a hand-off makes the scan thread stalled.
    stalled_after: Duration,
}

impl Beat {
    pub fn new(scan_period: Duration) -> Beat {
        Beat {
            epoch: Instant::now(),
            last: AtomicU64::new(0),
            stalled_after: scan_period * STALLED_AFTER,
        }
    }

    /// A hand-off now (scan thread).
    pub fn mark(&self) {
        let micros = u64::try_from(self.epoch.elapsed().as_micros()).unwrap_or(u64::MAX);
        self.last.store(micros.max(1), Ordering::Relaxed);
    }

    /// Whether the scan thread handed the outputs over recently.
    pub fn alive(&self) -> bool {
        let last = self.last.load(Ordering::Relaxed);
        last != 0 && self.epoch.elapsed().saturating_sub(Duration::from_micros(last)) <= self.stalled_after
    }
}

/// What the scan takes: the inputs in the order of the device's ranges
/// (discrete inputs in `bits`, input registers in `words`).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Inputs {
    pub bits: Vec<bool>,
    pub words: Vec<u16>,
    pub connected: bool,
    /// Errors so far, as the program reads them (saturating at 32767).
    pub errors: u16,
}

/// What the scan produced for the device, in the order of its output
/// ranges (coils in `bits`, holding registers in `words`).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Outputs {
    pub bits: Vec<bool>,
    pub words: Vec<u16>,
    /// Bumped when a scan changed a value; 0 before the first scan.
    pub generation: u64,
}

/// The device's state for the monitor and the JSON API.
#[derive(Clone, Debug, Default)]
pub struct State {
    pub connected: bool,
    pub errors: u64,
    pub last_error: Option<String>,
    /// When the latest complete poll ended.
    pub last_poll: Option<Instant>,
    pub polls: u64,
    /// Times the device was lost.
    pub losses: u64,
}

impl Inputs {
    /// Zeros for every input of `device`.
    pub fn sized(device: &Device) -> Inputs {
        let count = |table: InputTable| {
            device
                .inputs
                .iter()
                .filter(|i| i.table == table)
                .map(|i| usize::from(i.count))
                .sum()
        };
        Inputs {
            bits: vec![false; count(InputTable::DiscreteInputs)],
            words: vec![0; count(InputTable::InputRegisters)],
            connected: false,
            errors: 0,
        }
    }
}

impl Outputs {
    /// Zeros for every output of `device`.
    pub fn sized(device: &Device) -> Outputs {
        let count = |table: OutputTable| {
            device
                .outputs
                .iter()
                .filter(|o| o.table == table)
                .map(|o| usize::from(o.count))
                .sum()
        };
        Outputs {
            bits: vec![false; count(OutputTable::Coils)],
            words: vec![0; count(OutputTable::HoldingRegisters)],
            generation: 0,
        }
    }
}

impl Exchange {
    /// The slots of `devices`, those of one serial line sharing a signal;
    /// `scan_period` tells when the scan thread is stalled.
    pub fn new(devices: &[Device], scan_period: Duration) -> Exchange {
        let beat = Arc::new(Beat::new(scan_period));
        let mut slots: Vec<Arc<Slot>> = Vec::with_capacity(devices.len());
        for device in devices {
            let changed = slots
                .iter()
                .find(|slot| super::config::same_line(&slot.device, device))
                .map_or_else(
                    || Arc::new(super::wake::Signal::new()),
                    |slot| Arc::clone(&slot.changed),
                );
            slots.push(Arc::new(Slot {
                inputs: scan_lock::new(Inputs::sized(device)),
                outputs: scan_lock::new(Outputs::sized(device)),
                changed,
                state: Mutex::new(State::default()),
                beat: Arc::clone(&beat),
                device: device.clone(),
            }));
        }
        Exchange { slots }
    }

    /// The slots by link: one group per serial line (its devices in the
    /// file's order), one per TCP device.
    pub fn links(&self) -> Vec<Vec<Arc<Slot>>> {
        let mut links: Vec<Vec<Arc<Slot>>> = Vec::new();
        for slot in &self.slots {
            let line = links.iter_mut().find(|link| {
                link.first()
                    .is_some_and(|first| super::config::same_line(&first.device, &slot.device))
            });
            match line {
                Some(link) => link.push(Arc::clone(slot)),
                None => links.push(vec![Arc::clone(slot)]),
            }
        }
        links
    }

    /// Before a scan (scan thread): every device's freshest inputs, status
    /// relay and error count into the input image.
    pub fn to_engine(&self, engine: &mut dyn Engine) {
        let single = |device| HostDevice {
            device,
            width: Width::Single,
        };
        for slot in &self.slots {
            let inputs = lock(&slot.inputs);
            let (mut bits, mut words) = (inputs.bits.iter(), inputs.words.iter());
            for input in &slot.device.inputs {
                for n in input.to..input.to + u32::from(input.count) {
                    // The configuration keeps every device in its area, so
                    // a write does not fail.
                    let _ = match input.table {
                        InputTable::DiscreteInputs => engine.write(
                            single(Place::Bit(BitArea::X, n)),
                            i32::from(bits.next().copied().unwrap_or(false)),
                        ),
                        InputTable::InputRegisters => engine.write(
                            single(Place::Word(WordArea::D, n)),
                            i32::from(words.next().copied().unwrap_or(0) as i16),
                        ),
                    };
                }
            }
            let _ = engine.write(
                single(Place::Bit(BitArea::M, slot.device.status)),
                i32::from(inputs.connected),
            );
            let _ = engine.write(
                single(Place::Word(WordArea::D, slot.device.errors)),
                i32::from(inputs.errors),
            );
        }
    }

    /// After a scan (scan thread): every device's outputs from the image;
    /// a device whose outputs changed is told to write them.
    pub fn from_image(&self, image: &Memory) {
        if let Some(slot) = self.slots.first() {
            slot.beat.mark();
        }
        for slot in &self.slots {
            let mut outputs = lock(&slot.outputs);
            let Outputs {
                bits,
                words,
                generation,
            } = &mut *outputs;
            let (mut bit_at, mut word_at) = (0, 0);
            let mut changed = *generation == 0;
            for output in &slot.device.outputs {
                for k in 0..u32::from(output.count) {
                    match output.from {
                        Source::Bits(area, first) => {
                            let value = image.bit(area, first + k).unwrap_or(false);
                            if let Some(old) = bits.get_mut(bit_at) {
                                changed |= *old != value;
                                *old = value;
                            }
                            bit_at += 1;
                        }
                        Source::Words(first) => {
                            let value = image.word(WordArea::D, first + k).unwrap_or(0) as u16;
                            if let Some(old) = words.get_mut(word_at) {
                                changed |= *old != value;
                                *old = value;
                            }
                            word_at += 1;
                        }
                    }
                }
            }
            if changed {
                *generation += 1;
                drop(outputs);
                slot.changed.raise();
            }
        }
    }
}

impl Slot {
    /// A complete poll's inputs (poller): the scan takes them next.
    pub fn publish(&self, bits: &[bool], words: &[u16], errors: u64) {
        {
            let mut inputs = lock(&self.inputs);
            copy(&mut inputs.bits, bits);
            copy(&mut inputs.words, words);
            inputs.connected = true;
            inputs.errors = saturated(errors);
        }
        let mut state = self.state();
        state.connected = true;
        state.last_poll = Some(Instant::now());
        state.polls += 1;
    }

    /// A failed request or connection attempt (poller); `lost` when the
    /// device is now lost (its inputs held or cleared as configured).
    pub fn fail(&self, error: String, lost: bool) {
        let errors = {
            let mut state = self.state();
            state.errors += 1;
            state.last_error = Some(error);
            if lost && state.connected {
                state.losses += 1;
            }
            if lost {
                state.connected = false;
            }
            state.errors
        };
        let mut inputs = lock(&self.inputs);
        inputs.errors = saturated(errors);
        if lost {
            inputs.connected = false;
            if self.device.on_loss == OnLoss::Clear {
                inputs.bits.fill(false);
                inputs.words.fill(0);
            }
        }
    }

    /// The outputs when a scan changed them since `generation` (poller).
    pub fn outputs_since(&self, generation: u64, into: &mut Outputs) -> bool {
        let outputs = lock(&self.outputs);
        if outputs.generation == generation {
            return false;
        }
        copy(&mut into.bits, &outputs.bits);
        copy(&mut into.words, &outputs.words);
        into.generation = outputs.generation;
        true
    }

    /// The device's state (poller and monitor); a poller that panicked
    /// leaves plain values.
    pub fn state(&self) -> std::sync::MutexGuard<'_, State> {
        self.state.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
    }
}

/// Copies what both hold (they are sized from one device, so all of it).
fn copy<T: Copy>(target: &mut [T], source: &[T]) {
    for (to, from) in target.iter_mut().zip(source) {
        *to = *from;
    }
}

/// The error count as D holds it: it stops at 32767 rather than turn
/// negative.
fn saturated(errors: u64) -> u16 {
    u16::try_from(errors.min(32_767)).unwrap_or(32_767)
}

#[cfg(test)]
#[path = "exchange_tests.rs"]
mod tests;
