//! The program as a transition system: a state is the part of the device
//! image the program and the property file use (the program's compact
//! layout, which holds every device its instructions reach, its timers',
//! counters', STL and edge bookkeeping, and the devices the file names),
//! and one transition is one whole scan of the reference interpreter with
//! one choice of the free inputs and of the elapsed time.
//!
//! The interpreter is the specification, so the model is exact: every
//! instruction as DIALECT.md says, timers with the scan times given,
//! first-scan relays, operation errors. The explicit-state search over it
//! (`search.rs`) needs the reachable states to be few, which is what limits
//! it (`Limits`).

use crate::expr::Expr;
use crate::property::{Claim, Input, PropertyFile, ScanTime};
use ladder_front::host_device::HostDevice;
use ladder_front::program::CheckedProgram;
use ladder_interp::Interpreter;
use ladder_ir::image::{compact_layout, machine_use};
use ladder_runtime::layout::{Array, Layout, Scalar, FULL};
use ladder_runtime::{BitArea, Device, MachineUse, Memory, Width};

/// One choice made before a scan: the value of every free input (in the
/// order of `Model::inputs`) and the elapsed time.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Choice {
    pub values: Vec<i64>,
    pub elapsed_ms: u32,
}

pub struct Model<'p> {
    interpreter: Interpreter<'p>,
    machine: MachineUse,
    /// The byte ranges of `Memory` a state is made of.
    ranges: Vec<(usize, usize)>,
    pub inputs: Vec<Input>,
    pub scan_time: ScanTime,
    pub assumes: Vec<Expr>,
    /// The image before scan 1: power-up with `init` and `force` applied.
    pub power_up: Box<Memory>,
    /// The program's own layout (no host devices): what it reads or
    /// writes.
    program_layout: Layout,
    /// Whether states are keyed by the property file's cone of influence
    /// (else by the whole compact layout).
    pub cone: bool,
}

/// Why a model cannot be made.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ModelError(pub String);

impl<'p> Model<'p> {
    /// The model for checking `claim` (`None`: every property of `file`).
    pub fn new(
        checked: &'p CheckedProgram,
        ir: &ladder_ir::Program,
        file: &PropertyFile,
        claim: Option<&Claim>,
    ) -> Result<Model<'p>, ModelError> {
        let program_layout = compact_layout(checked, ir, &[]);
        // The roots of the cone: what this property (or every property of
        // the file) and the assumptions name.
        let named = named_devices(file, claim);
        let roots: Vec<(Array, u32)> = named
            .iter()
            .flat_map(|d| crate::coi::device_elements(d.device, d.width == Width::Double))
            .collect();
        let cone = crate::coi::cone(ir, &roots, machine_use(checked, ir, &named));
        let declared = match &file.inputs {
            Some(inputs) => inputs.clone(),
            None => program_layout
                .runs_of(Array::X)
                .flat_map(|run| run.first..run.first + run.count)
                .map(|n| Input::Bit(BitArea::X, n))
                .collect(),
        };
        // An input outside the cone cannot influence what the property
        // names: it is left OFF (its lowest value) instead of enumerated.
        let inputs: Vec<Input> = match &cone {
            Some(cone) => declared
                .into_iter()
                .filter(|&input| {
                    let (device, width) = input_device(input);
                    crate::coi::device_elements(device, width == Width::Double)
                        .into_iter()
                        .any(|(array, n)| cone.holds(array, n))
                })
                .collect(),
            None => declared,
        };
        let host_devices = host_devices(file, &named, &inputs);
        let layout = compact_layout(checked, ir, &host_devices);
        let machine = machine_use(checked, ir, &host_devices);
        let ranges = match &cone {
            Some(cone) => cone_ranges(cone, machine),
            None => layout_ranges(&layout, machine),
        };
        let merged = merge(ranges);
        let mut power_up = Memory::new_boxed();
        for (device, value) in &file.inits {
            if !power_up.write_device(device.device, device.width, *value) {
                return Err(ModelError(format!("`init` cannot write {:?}", device.device)));
            }
        }
        for &(area, index, on) in &file.forces {
            power_up
                .force(area, index, on)
                .map_err(|e| ModelError(format!("`force`: {e}")))?;
        }
        Ok(Model {
            interpreter: Interpreter::new(checked),
            machine,
            ranges: merged,
            inputs,
            scan_time: file.scan_time,
            assumes: file.assumes.clone(),
            power_up,
            program_layout,
            cone: cone.is_some(),
        })
    }

    /// The parts of the machine around the program the scan keeps.
    pub fn machine(&self) -> MachineUse {
        self.machine
    }

    /// Bytes of a state.
    pub fn state_size(&self) -> usize {
        self.ranges.iter().map(|(a, b)| b - a).sum()
    }

    /// How many choices each scan has (saturating).
    pub fn branching(&self) -> u64 {
        let (low, high) = (*self.scan_time.choices().start(), *self.scan_time.choices().end());
        let mut n = u64::from(high - low) + 1;
        for input in &self.inputs {
            let values = match *input {
                Input::Bit(..) => 2,
                Input::Word { low, high, .. } => (high - low + 1) as u64,
            };
            n = n.saturating_mul(values);
        }
        n
    }

    /// Every choice of a scan, in a fixed order (all inputs OFF or lowest
    /// first).
    pub fn choices(&self) -> Vec<Choice> {
        let mut out = vec![Choice {
            values: Vec::new(),
            elapsed_ms: 0,
        }];
        for input in &self.inputs {
            let (low, high) = match *input {
                Input::Bit(..) => (0, 1),
                Input::Word { low, high, .. } => (low, high),
            };
            out = out
                .into_iter()
                .flat_map(|c| {
                    (low..=high).map(move |v| {
                        let mut c = c.clone();
                        c.values.push(v);
                        c
                    })
                })
                .collect();
        }
        out.into_iter()
            .flat_map(|c| {
                self.scan_time.choices().map(move |ms| Choice {
                    values: c.values.clone(),
                    elapsed_ms: ms,
                })
            })
            .collect()
    }

    /// The state an image holds.
    pub fn key(&self, mem: &Memory) -> Box<[u8]> {
        let bytes = bytemuck::bytes_of(mem);
        let mut key = Vec::with_capacity(self.state_size());
        for &(start, end) in &self.ranges {
            key.extend_from_slice(&bytes[start..end]);
        }
        key.into_boxed_slice()
    }

    /// Writes a state into `mem` (a later scan's: the first-scan relays
    /// stay OFF).
    pub fn restore(&self, key: &[u8], mem: &mut Memory) {
        let bytes = bytemuck::bytes_of_mut(mem);
        let mut at = 0;
        for &(start, end) in &self.ranges {
            bytes[start..end].copy_from_slice(&key[at..at + (end - start)]);
            at += end - start;
        }
        mem.scan_count = mem.scan_count.max(1);
    }

    /// Writes the choice's inputs into `mem` (as a host's `set` before the
    /// scan) and tells whether every `assume` holds then.
    pub fn apply_inputs(&self, mem: &mut Memory, choice: &Choice) -> bool {
        let mut shown: Vec<(usize, u8)> = Vec::new();
        for (input, &value) in self.inputs.iter().zip(&choice.values) {
            let (device, width) = input_device(*input);
            mem.write_device(device, width, value as i32);
            // A host's X goes to the input image, which step 1 copies to
            // X: the assumptions read the new value ("this scan's inputs
            // written"), and X is put back before the scan, whose input
            // refresh compares it with the new one (high-speed counters).
            if let Input::Bit(BitArea::X, n) = *input {
                if let Some(x) = mem.x.get_mut(n as usize) {
                    shown.push((n as usize, *x));
                    *x = u8::from(value != 0);
                }
            }
        }
        let holds = self.assumes.iter().all(|a| a.holds(mem, mem));
        for (n, old) in shown {
            mem.x[n] = old;
        }
        holds
    }

    /// One whole scan.
    pub fn scan(&self, mem: &mut Memory, elapsed_ms: u32) {
        self.interpreter.scan_using(mem, elapsed_ms, self.machine);
    }

    /// Whether the program reads or writes `device` (some element of it
    /// is in the program's own layout), or the scan keeps it for a part of
    /// the machine the program uses (SM248 of the alarm monitor).
    pub fn program_uses(&self, device: HostDevice) -> bool {
        let elements = crate::coi::device_elements(device.device, device.width == Width::Double);
        if elements
            .iter()
            .any(|&(array, n)| self.program_layout.offset(array, n).is_some())
        {
            return true;
        }
        let part = match device.device {
            Device::Bit(area, n) | Device::Digits(area, n, _) => MachineUse::of_bits(area, n, n + 1),
            Device::Word(area, n) | Device::WordBit(area, n, _) => MachineUse::of_words(area, n, n + 1),
            Device::WideCounter(_) => MachineUse::NONE,
        };
        part != MachineUse::NONE && self.machine.contains(part)
    }
}

/// The byte ranges of a compact layout's arrays, and the scalars that
/// carry something from one scan to the next: the scan count matters only
/// as "is this the first scan", which a restored state says, and the clocks
/// only when the program shows them.
fn layout_ranges(layout: &Layout, machine: MachineUse) -> Vec<(usize, usize)> {
    let mut ranges = scalar_ranges(
        true,
        machine.contains(MachineUse::CLOCK_RELAYS),
        machine.contains(MachineUse::CALENDAR),
    );
    for array in Array::ALL {
        for run in layout.runs_of(array) {
            let Some(offset) = FULL.offset(array, run.first) else {
                continue;
            };
            ranges.push((offset, offset + run.count as usize * array.size()));
        }
    }
    ranges
}

/// The byte ranges of a cone of influence, with the scalars it needs: the
/// clocks only when the scan keeps the relays or the calendar that show
/// them (`machine`) and the cone holds those devices.
fn cone_ranges(cone: &crate::coi::Cone, machine: MachineUse) -> Vec<(usize, usize)> {
    let mut ranges = Vec::new();
    for &array in &cone.arrays {
        let Some(offset) = FULL.offset(array, array.first()) else {
            continue;
        };
        ranges.push((offset, offset + (array.end() - array.first()) as usize * array.size()));
    }
    for &(array, n) in &cone.elements {
        if cone.arrays.contains(&array) {
            continue;
        }
        let Some(offset) = FULL.offset(array, n) else { continue };
        ranges.push((offset, offset + array.size()));
    }
    // Step 2 looks at the pending table only when this says something is
    // pending.
    let pending = cone.arrays.contains(&Array::StlPendingOff)
        || cone.elements.iter().any(|(array, _)| *array == Array::StlPendingOff);
    let m = |range: std::ops::RangeInclusive<u32>| range.into_iter().any(|n| cone.holds(Array::M, n));
    let d = |range: std::ops::RangeInclusive<u32>| range.into_iter().any(|n| cone.holds(Array::D, n));
    let clock_relays = machine.contains(MachineUse::CLOCK_RELAYS) && m(8011..=8014);
    let calendar = machine.contains(MachineUse::CALENDAR) && (m(8015..=8019) || d(8013..=8019));
    ranges.extend(scalar_ranges(pending, clock_relays, calendar));
    ranges
}

/// The scan's scalars that carry something from one scan to the next and
/// that the state needs: the STL pending flag (step 2 looks at the pending
/// table only when it is set), the time the clock relays follow (and their
/// memory, kept with the calendar's flags), the calendar and its cache. The
/// scan count matters only as "is this the first scan", which a restored
/// state says; the elapsed time, the loop watchdog and the layout misses are
/// set anew every scan.
fn scalar_ranges(pending: bool, clock_relays: bool, calendar: bool) -> Vec<(usize, usize)> {
    let mut scalars = vec![Scalar::ForcedCount];
    if pending {
        scalars.push(Scalar::StlPendingAny);
    }
    if clock_relays || calendar {
        scalars.extend([Scalar::ClockMs, Scalar::CalendarFlags]);
    }
    if calendar {
        scalars.extend([
            Scalar::CalendarSeconds,
            Scalar::CalendarMs,
            Scalar::CalendarCacheAt,
            Scalar::CalendarCacheTime,
            Scalar::CalendarCacheYear,
        ]);
    }
    scalars.into_iter().map(|s| (s.offset(), s.offset() + 4)).collect()
}

/// Sorted, with overlapping and touching ranges joined.
fn merge(mut ranges: Vec<(usize, usize)>) -> Vec<(usize, usize)> {
    ranges.sort_unstable();
    let mut merged: Vec<(usize, usize)> = Vec::with_capacity(ranges.len());
    for (start, end) in ranges {
        match merged.last_mut() {
            Some(last) if start <= last.1 => last.1 = last.1.max(end),
            Some(_) | None => merged.push((start, end)),
        }
    }
    merged
}

/// The devices `claim` (or, without one, every property of the file) and
/// the assumptions name: the roots of the cone.
fn named_devices(file: &PropertyFile, claim: Option<&Claim>) -> Vec<HostDevice> {
    let mut named = Vec::new();
    let claims: Vec<&Claim> = match claim {
        Some(claim) => vec![claim],
        None => file.properties.iter().map(|p| &p.claim).collect(),
    };
    for claim in claims {
        for expr in claim.exprs() {
            expr.devices(&mut named);
        }
    }
    for assume in &file.assumes {
        assume.devices(&mut named);
    }
    named.into_iter().map(|(device, _)| device).collect()
}

/// The device and width an input is written as.
pub fn input_device(input: Input) -> (Device, Width) {
    match input {
        Input::Bit(area, n) => (Device::Bit(area, n), Width::Single),
        Input::Word { device, .. } => (device.device, device.width),
    }
}

/// The devices the file names: a compact layout holds them.
fn host_devices(file: &PropertyFile, named: &[HostDevice], inputs: &[Input]) -> Vec<HostDevice> {
    let mut devices = named.to_vec();
    devices.extend(file.inits.iter().map(|(device, _)| *device));
    for &(area, index, _) in &file.forces {
        devices.push(HostDevice {
            device: Device::Bit(area, index),
            width: Width::Single,
        });
    }
    for &input in inputs {
        let (device, width) = input_device(input);
        devices.push(HostDevice { device, width });
    }
    devices
}
