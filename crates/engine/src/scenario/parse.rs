//! Scenario files (docs/scenarios.md): one directive per line, `#` comments
//! outside the program block.

use ladder_front::diagnostics::Code;
use ladder_front::host_device::{parse_device, parse_number, parse_value, HostDevice};
use ladder_runtime::calendar::CalendarTime;
use ladder_runtime::BitArea;
use std::path::{Path, PathBuf};

/// Where the scenario's program comes from.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ProgramSource {
    /// `program FILE`, resolved against the scenario's folder.
    File(PathBuf),
    /// `program <<` ... `>>`: program line 1 is scenario line `first_line`.
    Inline { text: String, first_line: u32 },
}

#[derive(Clone, Debug, PartialEq)]
pub enum Directive {
    ScanMs(u32),
    Set {
        device: HostDevice,
        value: i32,
    },
    Force {
        area: BitArea,
        index: u32,
        on: bool,
    },
    Unforce {
        area: BitArea,
        index: u32,
    },
    Scan(u32),
    Expect {
        device: HostDevice,
        name: String,
        value: i32,
    },
    /// `expect error CODE` (Some) or `expect error none` (None).
    ExpectError(Option<u16>),
    /// `expect reject LINE [CODE]`: the program's first error is on that
    /// line, with that diagnostic code when one is given.
    ExpectReject {
        line: u32,
        code: Option<Code>,
    },
    /// `print DEV,...`: show the devices' values at this point.
    Print(Vec<(String, HostDevice)>),
    /// `expectf DEV VALUE [TOL]`: the real number in the pair (DEV+1, DEV)
    /// is VALUE, within TOL.
    ExpectReal {
        device: HostDevice,
        name: String,
        value: f32,
        tolerance: f32,
    },
    /// `pulse X0 N`: N rising edges of an input X0-X7 before the next scan.
    Pulse {
        input: u32,
        count: u32,
    },
    /// `clock YYYY-MM-DD HH:MM:SS`: the calendar clock before the next scan.
    Clock(CalendarTime),
}

#[derive(Clone, Debug, PartialEq)]
pub struct Step {
    pub directive: Directive,
    /// Line in the scenario file.
    pub line: u32,
}

#[derive(Clone, Debug)]
pub struct Scenario {
    pub path: PathBuf,
    pub program: ProgramSource,
    pub steps: Vec<Step>,
}

impl Scenario {
    /// The devices the scenario sets, forces, expects or prints: what a
    /// compact image must hold for it (with the inputs pulses go to).
    pub fn host_devices(&self) -> Vec<HostDevice> {
        let bit = |area: BitArea, index: u32| HostDevice {
            device: ladder_runtime::Device::Bit(area, index),
            width: ladder_runtime::Width::Single,
        };
        let mut devices = Vec::new();
        for step in &self.steps {
            match &step.directive {
                Directive::Set { device, .. } | Directive::Expect { device, .. } => devices.push(*device),
                Directive::ExpectReal { device, .. } => devices.push(*device),
                Directive::Force { area, index, .. } | Directive::Unforce { area, index } => {
                    devices.push(bit(*area, *index))
                }
                Directive::Print(list) => devices.extend(list.iter().map(|(_, device)| *device)),
                Directive::Pulse { input, .. } => devices.push(bit(BitArea::X, *input)),
                Directive::ScanMs(_)
                | Directive::Scan(_)
                | Directive::ExpectError(_)
                | Directive::ExpectReject { .. }
                | Directive::Clock(_) => {}
            }
        }
        devices
    }

    /// The `expect reject` expectation (program line, code) and the
    /// scenario line it is on, if the scenario expects a rejection.
    pub fn expected_reject(&self) -> Option<(u32, Option<Code>, u32)> {
        self.steps.iter().find_map(|step| match step.directive {
            Directive::ExpectReject { line, code } => Some((line, code, step.line)),
            Directive::ScanMs(_)
            | Directive::Set { .. }
            | Directive::Force { .. }
            | Directive::Unforce { .. }
            | Directive::Scan(_)
            | Directive::Expect { .. }
            | Directive::ExpectError(_)
            | Directive::Print(_)
            | Directive::ExpectReal { .. }
            | Directive::Pulse { .. }
            | Directive::Clock(_) => None,
        })
    }
}

/// A scenario that cannot be parsed: the file and line, and why.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ParseError {
    pub line: u32,
    pub message: String,
}

pub fn parse_scenario(path: &Path, text: &str) -> Result<Scenario, ParseError> {
    let (program, steps) = parse_steps(path, text)?;
    let program = program.ok_or(ParseError {
        line: 1,
        message: "no `program` directive".into(),
    })?;
    Ok(Scenario {
        path: path.to_path_buf(),
        program,
        steps,
    })
}

/// A stimulus file for `ladderc run --stimulus`: a scenario's directives,
/// its `program` line (if any) ignored, as the program is given apart.
pub fn parse_stimulus(path: &Path, text: &str) -> Result<Vec<Step>, ParseError> {
    let (_, steps) = parse_steps(path, text)?;
    if let Some(step) = steps
        .iter()
        .find(|s| matches!(s.directive, Directive::ExpectReject { .. }))
    {
        return Err(ParseError {
            line: step.line,
            message: "`expect reject` has no meaning in a stimulus".into(),
        });
    }
    Ok(steps)
}

fn parse_steps(path: &Path, text: &str) -> Result<(Option<ProgramSource>, Vec<Step>), ParseError> {
    let mut program = None;
    let mut steps = Vec::new();
    let mut lines = text.lines().enumerate().map(|(i, l)| (i as u32 + 1, l));
    let mut rejecting = false;
    while let Some((line, raw)) = lines.next() {
        let error = |message: String| ParseError { line, message };
        let content = raw.split('#').next().unwrap_or("").trim();
        let words: Vec<&str> = content.split_whitespace().collect();
        let Some((&keyword, args)) = words.split_first() else {
            continue;
        };
        let keyword = keyword.to_ascii_lowercase();
        let directive = match (keyword.as_str(), args) {
            ("program", _) if program.is_some() => return Err(error("a scenario has one program".into())),
            ("program", ["<<"]) => {
                let first_line = line + 1;
                let mut body = String::new();
                loop {
                    let Some((_, program_line)) = lines.next() else {
                        return Err(error("`program <<` without a closing `>>` line".into()));
                    };
                    // Trailing blanks after `>>` are easy to leave and hard to see.
                    if program_line.trim_end() == ">>" {
                        break;
                    }
                    body.push_str(program_line);
                    body.push('\n');
                }
                program = Some(ProgramSource::Inline { text: body, first_line });
                continue;
            }
            ("program", [file]) => {
                let base = path.parent().unwrap_or(Path::new("."));
                program = Some(ProgramSource::File(base.join(file)));
                continue;
            }
            ("scan-ms", [ms]) => Directive::ScanMs(number(ms, 0, u32::MAX.into()).map_err(error)? as u32),
            ("scan", []) => Directive::Scan(1),
            ("scan", [n]) => Directive::Scan(number(n, 0, u32::MAX.into()).map_err(error)? as u32),
            ("set" | "set32", [device, value]) => {
                let device = parse_device(device, keyword == "set32").map_err(error)?;
                let value = parse_value(value, device).map_err(error)?;
                Directive::Set { device, value }
            }
            ("setf", [device, value]) => {
                let device = parse_device(device, true).map_err(error)?;
                let value = real(value).map_err(error)?;
                Directive::Set {
                    device,
                    value: value.to_bits() as i32,
                }
            }
            ("expectf", [device, value, tolerance @ ..]) if tolerance.len() <= 1 => {
                let parsed = parse_device(device, true).map_err(error)?;
                let tolerance = match tolerance.first() {
                    Some(text) => real(text).map_err(error)?.abs(),
                    None => 0.0,
                };
                Directive::ExpectReal {
                    device: parsed,
                    name: device.to_string(),
                    value: real(value).map_err(error)?,
                    tolerance,
                }
            }
            ("pulse", [device, count]) => {
                let input = match parse_device(device, false).map_err(error)?.device {
                    ladder_runtime::Device::Bit(BitArea::X, n) if n < ladder_runtime::device::HSC_INPUTS => n,
                    ladder_runtime::Device::Bit(..)
                    | ladder_runtime::Device::Word(..)
                    | ladder_runtime::Device::WordBit(..)
                    | ladder_runtime::Device::Digits(..)
                    | ladder_runtime::Device::WideCounter(_) => {
                        return Err(error(format!("`{device}`: pulses are counted on inputs X0..X7")))
                    }
                };
                let count = number(count, 0, u32::MAX.into()).map_err(error)? as u32;
                Directive::Pulse { input, count }
            }
            ("clock", [date, time]) => Directive::Clock(calendar(date, time).map_err(error)?),
            ("force", [device, value]) => {
                let (area, index) = forceable(device).map_err(error)?;
                let on = match value.to_ascii_lowercase().as_str() {
                    "1" | "on" => true,
                    "0" | "off" => false,
                    _ => return Err(error(format!("`{value}` is not a bit value (0, 1, on, off)"))),
                };
                Directive::Force { area, index, on }
            }
            ("unforce", [device]) => {
                let (area, index) = forceable(device).map_err(error)?;
                Directive::Unforce { area, index }
            }
            ("expect", ["error", code]) => Directive::ExpectError(if code.eq_ignore_ascii_case("none") {
                None
            } else {
                Some(error_code(code).map_err(error)?)
            }),
            ("expect", ["reject", program_line, code @ ..]) if code.len() <= 1 => {
                rejecting = true;
                let line = number(program_line, 1, u32::MAX.into()).map_err(error)? as u32;
                let code = match code.first() {
                    None => None,
                    Some(text) => Some(
                        text.parse::<Code>()
                            .map_err(|()| error(format!("`{text}` is not a diagnostic code such as E0013")))?,
                    ),
                };
                Directive::ExpectReject { line, code }
            }
            ("expect" | "expect32", [device, value]) => {
                let parsed = parse_device(device, keyword == "expect32").map_err(error)?;
                let value = parse_value(value, parsed).map_err(error)?;
                Directive::Expect {
                    device: parsed,
                    name: device.to_string(),
                    value,
                }
            }
            ("print", devices) if !devices.is_empty() => {
                let mut printed = Vec::new();
                for name in devices.iter().flat_map(|d| d.split(',')).filter(|d| !d.is_empty()) {
                    let (bare, double) = match name.strip_suffix(":32") {
                        Some(bare) => (bare, true),
                        None => (name, false),
                    };
                    let device = parse_device(bare, double).map_err(error)?;
                    printed.push((name.to_string(), device));
                }
                Directive::Print(printed)
            }
            (
                known @ ("scan-ms" | "scan" | "set" | "set32" | "setf" | "force" | "unforce" | "expect" | "expect32"
                | "expectf" | "print" | "pulse" | "clock"),
                _,
            ) => {
                return Err(error(format!("wrong arguments for `{known}`")));
            }
            _ => return Err(error(format!("unknown directive `{keyword}`"))),
        };
        let runs_program = matches!(
            directive,
            Directive::Scan(_) | Directive::Expect { .. } | Directive::ExpectError(_) | Directive::ExpectReal { .. }
        );
        if rejecting && runs_program {
            return Err(error("nothing may run after `expect reject`".into()));
        }
        steps.push(Step { directive, line });
    }
    Ok((program, steps))
}

/// A real number: decimal (`1.5`, `-2.5e3`) or in E notation
/// (`E1.234+3`).
pub fn real(text: &str) -> Result<f32, String> {
    let bad = || format!("`{text}` is not a real number such as 1.5, -2.5e3 or E1.234+3");
    if text.starts_with(['E', 'e']) {
        return match ladder_front::syntax::operand::parse_operand(text, 0) {
            Ok(ladder_front::syntax::Operand {
                syntax: ladder_front::syntax::OperandSyntax::Real(r),
                ..
            }) => Ok(r.value),
            _ => Err(bad()),
        };
    }
    let value: f32 = text.parse().map_err(|_| bad())?;
    if value.is_finite() {
        Ok(value)
    } else {
        Err(bad())
    }
}

/// `YYYY-MM-DD HH:MM:SS`.
fn calendar(date: &str, time: &str) -> Result<CalendarTime, String> {
    let bad = || format!("`{date} {time}` is not a time such as 2026-01-02 03:04:05 (1980-2079)");
    let fields = |text: &str, separator: char| -> Option<Vec<u32>> {
        let parts: Vec<u32> = text.split(separator).map(|p| p.parse().ok()).collect::<Option<_>>()?;
        (parts.len() == 3).then_some(parts)
    };
    let (Some(d), Some(t)) = (fields(date, '-'), fields(time, ':')) else {
        return Err(bad());
    };
    let when = CalendarTime {
        year: d[0],
        month: d[1],
        day: d[2],
        hour: t[0],
        minute: t[1],
        second: t[2],
        weekday: 0,
    };
    when.to_seconds().map(|_| when).ok_or_else(bad)
}

fn number(text: &str, min: i64, max: i64) -> Result<i64, String> {
    let value = parse_number(text)?;
    if !(min..=max).contains(&value) {
        return Err(format!("`{text}` is out of range"));
    }
    Ok(value)
}

/// Error codes are hex by convention: `4085`, `4085H` and `H4085` all mean
/// 4085H; `K16517` is the same code in decimal.
fn error_code(text: &str) -> Result<u16, String> {
    let value = if text.starts_with(['K', 'k']) {
        parse_number(text)?
    } else {
        let hex = text.trim_start_matches(['H', 'h']).trim_end_matches(['H', 'h']);
        i64::from_str_radix(hex, 16).map_err(|_| format!("`{text}` is not an error code such as 4085H"))?
    };
    u16::try_from(value).map_err(|_| format!("`{text}` is not an error code"))
}

fn forceable(text: &str) -> Result<(BitArea, u32), String> {
    match parse_device(text, false)?.device {
        ladder_runtime::Device::Bit(
            area @ (BitArea::X | BitArea::Y | BitArea::M | BitArea::TimerContact | BitArea::CounterContact),
            index,
        ) => Ok((area, index)),
        ladder_runtime::Device::Bit(BitArea::S | BitArea::Sm, _)
        | ladder_runtime::Device::Word(..)
        | ladder_runtime::Device::WordBit(..)
        | ladder_runtime::Device::Digits(..)
        | ladder_runtime::Device::WideCounter(_) => Err(format!("`{text}` cannot be forced (X, Y, M, T and C can)")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<Scenario, ParseError> {
        parse_scenario(Path::new("dir/t.scn"), text)
    }

    #[test]
    fn the_example_of_the_spec() {
        let scenario = parse(
            "program <<\nLD X0\nOR Y0\nANI X1\nOUT Y0\n>>\nset X0 1\nscan\nexpect Y0 1\nset X0 0\nscan 3\nexpect Y0 1      # sealed in\n",
        )
        .unwrap();
        assert_eq!(
            scenario.program,
            ProgramSource::Inline {
                text: "LD X0\nOR Y0\nANI X1\nOUT Y0\n".into(),
                first_line: 2
            }
        );
        assert_eq!(scenario.steps.len(), 6);
        assert_eq!(scenario.steps[4].directive, Directive::Scan(3));
        assert_eq!(scenario.steps[5].line, 12);
    }

    #[test]
    fn program_files_are_relative_to_the_scenario() {
        let scenario = parse("program ../x.il\n").unwrap();
        assert_eq!(scenario.program, ProgramSource::File(PathBuf::from("dir/../x.il")));
    }

    #[test]
    fn errors_and_rejects() {
        let scenario = parse("program p.il\nexpect error 4085H\nexpect error none\nexpect error K16517").unwrap();
        let codes: Vec<_> = scenario.steps.iter().map(|s| s.directive.clone()).collect();
        assert_eq!(
            codes,
            [
                Directive::ExpectError(Some(0x4085)),
                Directive::ExpectError(None),
                Directive::ExpectError(Some(0x4085))
            ]
        );
        assert_eq!(
            parse("program p.il\nexpect reject 3\n").unwrap().expected_reject(),
            Some((3, None, 2))
        );
        assert_eq!(
            parse("program p.il\nexpect reject 3 e0013\n")
                .unwrap()
                .expected_reject(),
            Some((3, Some(Code::PendingBlocks), 2))
        );
        assert!(parse("program p.il\nexpect reject 3 E9999\n").is_err());
        assert!(parse("program p.il\nexpect reject 3 E0013 x\n").is_err());
        assert_eq!(parse("program p.il\nexpect reject 3\nscan\n").unwrap_err().line, 3);
    }

    #[test]
    fn machine_directives() {
        let scenario = parse(
            "program p.il\nsetf D0 1.5\nexpectf D0 E1.5 0.01\npulse X1 5\nclock 2026-01-02 03:04:05\nset U1\\G3 7\n",
        )
        .unwrap();
        let steps: Vec<_> = scenario.steps.iter().map(|s| s.directive.clone()).collect();
        assert!(matches!(steps[0], Directive::Set { value, .. } if value == 1.5f32.to_bits() as i32));
        assert!(
            matches!(steps[1], Directive::ExpectReal { value, tolerance, .. } if value == 1.5 && tolerance == 0.01)
        );
        assert_eq!(steps[2], Directive::Pulse { input: 1, count: 5 });
        assert!(matches!(
            steps[3],
            Directive::Clock(CalendarTime {
                year: 2026,
                second: 5,
                ..
            })
        ));
        assert!(
            parse("program p.il\npulse X10 1\n").is_err(),
            "X10 is not a counter input"
        );
        assert!(parse("program p.il\nclock 2026-02-30 00:00:00\n").is_err());
        assert!(parse("program p.il\nsetf D0 nan\n").is_err());
    }

    #[test]
    fn bad_scenarios_say_where() {
        assert_eq!(parse("set X0 1\n").unwrap_err().message, "no `program` directive");
        assert_eq!(parse("program p.il\nfrobnicate\n").unwrap_err().line, 2);
        assert_eq!(parse("program p.il\nforce D0 1\n").unwrap_err().line, 2);
        assert_eq!(parse("program <<\nLD X0\n").unwrap_err().line, 1);
        assert!(parse("program p.il\nset D0 70000\n").is_err());
    }
}
