//! A compiled program running in a host process, as a scenario engine.

use super::toolchain;
use crate::pipeline::{ImageRequest, Lowered};
use crate::{Engine, EngineError};
use ladder_codegen::ObjectOptions;
use ladder_front::host_device::HostDevice;
use ladder_runtime::calendar::CalendarTime;
use ladder_runtime::host::{read_composite, write_composite, AccessError, Basic, BasicAccess};
use ladder_runtime::BitArea;
use std::io::{BufRead, BufReader, Write};
use std::process::{Child, ChildStdin, ChildStdout, Command, Stdio};

const SCENARIO_HOST: &str = include_str!("scenario_host.c");

/// How the program gets into the host.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Route {
    /// Cranelift's object file.
    Object,
    /// The C back end's source, compiled with the host (at -O2).
    C,
}

/// A host process running the compiled program.
pub struct AotEngine {
    child: Child,
    input: ChildStdin,
    output: BufReader<ChildStdout>,
    /// Holds the host executable until the engine is dropped.
    _work: tempfile::TempDir,
}

impl AotEngine {
    /// Compiles `program` (to an object, or to C compiled by the C
    /// compiler) for an image as `image` asks, links the scenario host and
    /// starts it.
    pub fn start(lowered: &Lowered<'_>, route: Route, image: &ImageRequest) -> Result<AotEngine, EngineError> {
        let compiler = toolchain::c_compiler().map_err(EngineError::Unavailable)?;
        let runtime = toolchain::runtime_library().map_err(EngineError::Unavailable)?;
        let failed = |e: String| EngineError::Failed(e);
        let work = tempfile::tempdir().map_err(|e| failed(e.to_string()))?;
        let options = ObjectOptions {
            target: None,
            prefix: ladder_codegen::DEFAULT_PREFIX.to_string(),
            layout: None,
            ..Default::default()
        };
        let program_path = match route {
            Route::Object => {
                let object = lowered
                    .object(&options, image)
                    .map_err(|e| failed(e.to_string()))?
                    .output;
                let path = work.path().join("program.o");
                std::fs::write(&path, object).map_err(|e| failed(e.to_string()))?;
                path
            }
            Route::C => {
                let c_options = ladder_cback::COptions {
                    prefix: options.prefix.clone(),
                    source_name: "scenario program".to_string(),
                    layout: None,
                    ..Default::default()
                };
                let path = work.path().join("program.c");
                std::fs::write(&path, lowered.c_source(&c_options, image).output).map_err(|e| failed(e.to_string()))?;
                path
            }
        };
        let host_object = work.path().join("scenario_host.o");
        let host = work.path().join("scenario_host");
        let compiled = toolchain::compiled_once(&compiler, "scenario_host", SCENARIO_HOST).map_err(failed)?;
        std::fs::write(&host_object, compiled).map_err(|e| failed(e.to_string()))?;
        toolchain::link_host(&compiler, work.path(), &[host_object, program_path], &runtime, &host).map_err(failed)?;
        let mut child = Command::new(&host)
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::inherit())
            .spawn()
            .map_err(|e| failed(format!("cannot start the host: {e}")))?;
        let input = child.stdin.take().expect("piped");
        let output = BufReader::new(child.stdout.take().expect("piped"));
        Ok(AotEngine {
            child,
            input,
            output,
            _work: work,
        })
    }

    /// Sends one command and returns its one-line answer.
    fn ask(&mut self, command: &str) -> Result<String, String> {
        writeln!(self.input, "{command}")
            .and_then(|()| self.input.flush())
            .map_err(|e| self.gone(e))?;
        let mut answer = String::new();
        match self.output.read_line(&mut answer) {
            Ok(0) => Err(self.gone("no answer")),
            Ok(_) => Ok(answer.trim().to_string()),
            Err(e) => Err(self.gone(e)),
        }
    }

    fn gone(&mut self, why: impl std::fmt::Display) -> String {
        let status = self.child.try_wait().ok().flatten();
        format!("the host process stopped answering ({why}; exit status {status:?})")
    }

    /// A command answered by a LadderStatus.
    fn status(&mut self, command: &str) -> Result<(), String> {
        let answer = self.ask(command)?;
        match answer.as_str() {
            "0" => Ok(()),
            "1" => Err("out of range".into()),
            "2" => Err("not forceable".into()),
            "3" => Err(format!(
                "the C API refused the arguments of `{command}` (LADDER_STATUS_BAD_ARGUMENT)"
            )),
            "4" => Err(format!(
                "the C API refused the value of `{command}` as not fitting the device (LADDER_STATUS_BAD_VALUE)"
            )),
            "5" => Err(NOT_IN_IMAGE.into()),
            misses if misses.starts_with("M ") => Err(format!(
                "the program wrote {} time(s) to devices its compact image lacks (ladder_layout_misses): \
                 a compiler error, please report it",
                &misses[2..]
            )),
            other => Err(format!("the host gave an unknown answer `{other}` to `{command}`")),
        }
    }
}

/// `LADDER_STATUS_NOT_IN_IMAGE` as `status` reports it.
const NOT_IN_IMAGE: &str = "not in the program's compact image";

/// The C API's (kind, number) of a basic device.
fn kind(device: Basic) -> (u32, u32) {
    let (kind, number) = ladder_runtime::capi::c_device(device);
    (kind as u32, number)
}

impl BasicAccess for AotEngine {
    fn read_basic(&mut self, device: Basic) -> Result<i32, AccessError> {
        let (kind, number) = kind(device);
        let answer = self
            .ask(&format!("r {kind} {number}"))
            .map_err(AccessError::Unreachable)?;
        if let Some(status) = answer.strip_prefix('E') {
            return Err(match status.trim() {
                "5" => AccessError::NotInImage,
                _ => AccessError::OutOfRange,
            });
        }
        answer
            .parse()
            .map_err(|_| AccessError::Unreachable(format!("host answered `{answer}`")))
    }

    fn write_basic(&mut self, device: Basic, value: i32) -> Result<(), AccessError> {
        let (kind, number) = kind(device);
        self.status(&format!("w {kind} {number} {value}"))
            .map_err(|e| match e.as_str() {
                "out of range" => AccessError::OutOfRange,
                NOT_IN_IMAGE => AccessError::NotInImage,
                _ => AccessError::Unreachable(e),
            })
    }
}

fn describe(error: AccessError, device: HostDevice) -> String {
    match error {
        AccessError::OutOfRange => format!("{:?} is out of range", device.device),
        AccessError::ReadOnly => format!("{:?} is read-only here", device.device),
        AccessError::NotInImage => format!("{:?} is not in the program's image", device.device),
        AccessError::Unreachable(why) => why,
    }
}

impl Engine for AotEngine {
    fn read(&mut self, device: HostDevice) -> Result<i32, String> {
        read_composite(self, device.device, device.width).map_err(|e| describe(e, device))
    }

    fn write(&mut self, device: HostDevice, value: i32) -> Result<(), String> {
        write_composite(self, device.device, device.width, value).map_err(|e| describe(e, device))
    }

    fn force(&mut self, area: BitArea, index: u32, on: bool) -> Result<(), String> {
        let (kind, number) = kind(Basic::Bit(area, index));
        self.status(&format!("f {kind} {number} {}", on as u8))
    }

    fn unforce(&mut self, area: BitArea, index: u32) -> Result<(), String> {
        let (kind, number) = kind(Basic::Bit(area, index));
        self.status(&format!("u {kind} {number}"))
    }

    fn scan(&mut self, elapsed_ms: u32) -> Result<(), String> {
        self.status(&format!("s 1 {elapsed_ms}"))
    }

    fn pulse(&mut self, input: u32, count: u32) -> Result<(), String> {
        self.status(&format!("p {input} {count}"))
    }

    fn set_clock(&mut self, time: CalendarTime) -> Result<(), String> {
        let CalendarTime {
            year,
            month,
            day,
            hour,
            minute,
            second,
            ..
        } = time;
        self.status(&format!("c {year} {month} {day} {hour} {minute} {second}"))
    }
}

impl Drop for AotEngine {
    fn drop(&mut self) {
        let _ = writeln!(self.input, "q");
        let _ = self.input.flush();
        let _ = self.child.wait();
    }
}
