//! Driving one engine through a scenario's directives, telling an observer
//! after every scan and at every `print`: the scenario runner records
//! waveforms and printed values with it, `ladderc run --stimulus` prints
//! the watched devices.

use super::parse::{Directive, Step};
use crate::Engine;
use ladder_front::host_device::{format_value, same_bits, HostDevice};
use ladder_runtime::special::{D_ERROR_CODE, D_ERROR_LINE, M_OPERATION_ERROR};
use ladder_runtime::{BitArea, Device, Width, WordArea};

/// What happens while a scenario is driven.
pub trait Observer {
    /// Before the first directive.
    fn started(&mut self, _engine: &mut dyn Engine) -> Result<(), String> {
        Ok(())
    }
    /// A scan finished: its number (from 1) and the time reported so far.
    fn scanned(&mut self, engine: &mut dyn Engine, scan: u64, time_ms: u64) -> Result<(), String>;
    /// A `print` directive at scenario `line`: the devices and their values.
    fn printed(&mut self, line: u32, scan: u64, values: Vec<(String, HostDevice, i32)>);
    /// An expectation at scenario `line` failed after (scans, time in ms),
    /// with the engine as it is then.
    fn failed(&mut self, _engine: &mut dyn Engine, _line: u32, _after: (u64, u64), _message: &str) {}
}

/// M8067, D8067 and D8069: the operation error flag, its code and line.
pub const ERROR_FLAG: HostDevice = HostDevice {
    device: Device::Bit(BitArea::M, M_OPERATION_ERROR),
    width: Width::Single,
};
pub const ERROR_CODE: HostDevice = HostDevice {
    device: Device::Word(WordArea::D, D_ERROR_CODE),
    width: Width::Single,
};
pub const ERROR_LINE: HostDevice = HostDevice {
    device: Device::Word(WordArea::D, D_ERROR_LINE),
    width: Width::Single,
};

/// Drives one engine through the directives: (scenario line, message) per
/// failed expectation. An engine fault ends the run with one failure.
pub fn drive(steps: &[Step], engine: &mut dyn Engine, observer: &mut dyn Observer) -> Vec<(u32, String)> {
    let mut failures = Vec::new();
    let mut scan_ms = 10;
    let (mut scans, mut time_ms) = (0u64, 0u64);
    if let Err(fault) = observer.started(engine) {
        return vec![(steps.first().map_or(1, |s| s.line), format!("engine fault: {fault}"))];
    }
    for step in steps {
        let result: Result<(), String> = (|| {
            match &step.directive {
                Directive::ScanMs(ms) => scan_ms = *ms,
                Directive::Set { device, value } => engine.write(*device, *value)?,
                Directive::Force { area, index, on } => engine.force(*area, *index, *on)?,
                Directive::Unforce { area, index } => engine.unforce(*area, *index)?,
                Directive::Scan(n) => {
                    for _ in 0..*n {
                        engine.scan(scan_ms)?;
                        scans += 1;
                        time_ms += u64::from(scan_ms);
                        observer.scanned(engine, scans, time_ms)?;
                    }
                }
                Directive::Print(devices) => {
                    let mut values = Vec::with_capacity(devices.len());
                    for (name, device) in devices {
                        values.push((name.clone(), *device, engine.read(*device)?));
                    }
                    observer.printed(step.line, scans, values);
                }
                Directive::Expect { device, name, value } => {
                    let actual = engine.read(*device)?;
                    if !same_bits(actual, *value, device.bits()) {
                        failures.push((
                            step.line,
                            format!(
                                "expected {name} = {}, got {}",
                                format_value(*value, *device),
                                format_value(actual, *device)
                            ),
                        ));
                    }
                }
                Directive::ExpectError(expected) => {
                    let flag = engine.read(ERROR_FLAG)? != 0;
                    let code = engine.read(ERROR_CODE)? as u16;
                    let actual = flag.then_some(code);
                    if actual != *expected {
                        let show = |c: Option<u16>| c.map_or("none".to_string(), |c| format!("{c:04X}H"));
                        failures.push((
                            step.line,
                            format!("expected error {}, got {}", show(*expected), show(actual)),
                        ));
                    }
                }
                Directive::ExpectReal {
                    device,
                    name,
                    value,
                    tolerance,
                } => {
                    let actual = f32::from_bits(engine.read(*device)? as u32);
                    let close = actual == *value || (actual - value).abs() <= *tolerance;
                    if !close {
                        let within = if *tolerance > 0.0 {
                            format!(" (within {tolerance:e})")
                        } else {
                            String::new()
                        };
                        failures.push((
                            step.line,
                            format!("expected {name} = {value:e}{within}, got {actual:e}"),
                        ));
                    }
                }
                Directive::Pulse { input, count } => engine.pulse(*input, *count)?,
                Directive::Clock(time) => engine.set_clock(*time)?,
                Directive::ExpectReject { .. } => {}
            }
            Ok(())
        })();
        if let Err(fault) = result {
            failures.push((step.line, format!("engine fault: {fault}")));
            break;
        }
        if let Some((line, message)) = failures.last().filter(|(line, _)| *line == step.line) {
            observer.failed(engine, *line, (scans, time_ms), message);
        }
    }
    failures
}
