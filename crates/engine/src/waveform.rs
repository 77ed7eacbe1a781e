//! Waveforms of a run: the values of some devices after every scan, with the
//! reported elapsed time as the time axis, written as a VCD file (1 ms
//! timescale) that GTKWave and other waveform viewers open. Bits are wires,
//! words 16- or 32-bit vectors.

use crate::Engine;
use ladder_front::host_device::HostDevice;
use ladder_runtime::{BitArea, Device, Width, WordArea};

/// A device as a person writes it: `X17`, `D0.F`, `K4M0`, `CN200`,
/// `D10:32` for a 32-bit pair.
pub fn device_name(device: HostDevice) -> String {
    let name = match device.device {
        // Timers and counters by what is meant: contact or current value.
        Device::Bit(BitArea::TimerContact, n) => format!("TS{n}"),
        Device::Bit(BitArea::CounterContact, n) => format!("CS{n}"),
        Device::Word(WordArea::TimerValue, n) => format!("TN{n}"),
        Device::Word(WordArea::CounterValue, n) => format!("CN{n}"),
        Device::Bit(area, n) => area.device_name(n),
        Device::Word(area, n) => area.device_name(n),
        Device::WordBit(area, n, bit) => format!("{}.{bit:X}", area.device_name(n)),
        Device::Digits(area, start, digits) => format!("K{digits}{}", area.device_name(start)),
        Device::WideCounter(n) => format!("CN{n}"),
    };
    match (device.device, device.width) {
        (Device::Word(..), Width::Double) => format!("{name}:32"),
        (Device::Word(..), Width::Single)
        | (
            Device::Bit(..) | Device::WordBit(..) | Device::Digits(..) | Device::WideCounter(_),
            Width::Single | Width::Double,
        ) => name,
    }
}

/// Bits of a device's value as a signal: a digit group has 4 per digit.
fn signal_bits(device: HostDevice) -> u32 {
    match device.device {
        Device::Digits(_, _, digits) => 4 * u32::from(digits),
        Device::Bit(..) | Device::Word(..) | Device::WordBit(..) | Device::WideCounter(_) => device.bits(),
    }
}

/// A recorded or watched device: its name as shown, the device, and
/// whether its 32 bits are a real number (`D0:float`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Signal {
    pub name: String,
    pub device: HostDevice,
    pub real: bool,
}

impl Signal {
    /// A device shown as an integer, named as a programmer writes it.
    pub fn of(device: HostDevice) -> Signal {
        Signal {
            name: device_name(device),
            device,
            real: false,
        }
    }

    /// The value as text: a real number in its shortest exact decimal form,
    /// anything else as `format` says.
    pub fn show(&self, value: i32, format: impl FnOnce(i32, HostDevice) -> String) -> String {
        if self.real {
            format!("{:?}", f32::from_bits(value as u32))
        } else {
            format(value, self.device)
        }
    }
}

/// Values of the recorded devices over time.
#[derive(Clone, Debug)]
pub struct Recorder {
    signals: Vec<Signal>,
    /// (time in ms, value of every signal), times increasing.
    samples: Vec<(u64, Vec<i32>)>,
    /// The time of the latest sample, kept or not: the end of the run.
    end_ms: u64,
}

impl Recorder {
    pub fn new(signals: Vec<Signal>) -> Recorder {
        Recorder {
            signals,
            samples: Vec::new(),
            end_ms: 0,
        }
    }

    pub fn signals(&self) -> &[Signal] {
        &self.signals
    }

    /// (time in ms, value of every signal) where something changed.
    pub fn samples(&self) -> &[(u64, Vec<i32>)] {
        &self.samples
    }

    /// The time the run ended at.
    pub fn end_ms(&self) -> u64 {
        self.end_ms
    }

    /// Reads every signal at `time_ms`; kept only when something changed,
    /// so a long run with few changes stays small. Scans that report 0 ms
    /// share a time: the last one's values stand for it.
    pub fn sample(&mut self, engine: &mut dyn Engine, time_ms: u64) -> Result<(), String> {
        let mut values = Vec::with_capacity(self.signals.len());
        for signal in &self.signals {
            values.push(engine.read(signal.device)?);
        }
        self.end_ms = self.end_ms.max(time_ms);
        let changed = self.samples.last().is_none_or(|(_, previous)| *previous != values);
        // The first sample (the values before the first scan) stays.
        let replaces_last = self.samples.len() > 1 && self.samples.last().is_some_and(|(last, _)| *last == time_ms);
        if replaces_last {
            if let Some(last) = self.samples.last_mut() {
                last.1 = values;
            }
        } else if changed {
            self.samples.push((time_ms, values));
        }
        Ok(())
    }

    /// The recording as a VCD file.
    pub fn to_vcd(&self) -> std::io::Result<Vec<u8>> {
        use vcd::{SimulationCommand, TimescaleUnit, Value, VarType};
        let mut writer = vcd::Writer::new(Vec::new());
        writer.timescale(1, TimescaleUnit::MS)?;
        writer.add_module("ladderc")?;
        let mut ids = Vec::with_capacity(self.signals.len());
        for signal in &self.signals {
            // VCD names hold no blanks; ours never do.
            let id = if signal.real {
                writer.add_var(VarType::Real, 32, &signal.name, None)?
            } else {
                writer.add_wire(signal_bits(signal.device), &signal.name)?
            };
            ids.push(id);
        }
        writer.upscope()?;
        writer.enddefinitions()?;
        let bits = |value: i32, width: u32| {
            (0..width).rev().map(move |bit| {
                if (value as u32 >> bit) & 1 != 0 {
                    Value::V1
                } else {
                    Value::V0
                }
            })
        };
        let mut previous: Option<&Vec<i32>> = None;
        for (index, (time, values)) in self.samples.iter().enumerate() {
            writer.timestamp(*time)?;
            if index == 0 {
                writer.begin(SimulationCommand::Dumpvars)?;
            }
            for (index, (signal, id)) in self.signals.iter().zip(&ids).enumerate() {
                let value = &values[index];
                if previous.is_some_and(|p| p.get(index) == Some(value)) {
                    continue;
                }
                match (signal.real, signal_bits(signal.device)) {
                    (true, _) => writer.change_real(*id, f64::from(f32::from_bits(*value as u32)))?,
                    (false, 1) => writer.change_scalar(*id, if *value != 0 { Value::V1 } else { Value::V0 })?,
                    (false, width) => writer.change_vector(*id, bits(*value, width))?,
                }
            }
            if index == 0 {
                writer.end()?;
            }
            previous = Some(values);
        }
        // The run's end, so that a viewer shows all of it and not only up
        // to the last change.
        if self.samples.last().is_some_and(|(last, _)| *last < self.end_ms) {
            writer.timestamp(self.end_ms)?;
        }
        Ok(std::mem::take(writer.writer()))
    }
}
