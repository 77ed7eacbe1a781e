//! The engines: what runs a checked program, scan by scan. The in-process
//! ones (interpreter, JIT) work on a `Memory` directly; `aot` (the object
//! file) and `c` (the C back end's source) talk to a host process through
//! the C API (`crate::aot`). Everything that runs programs — scenarios,
//! `run`, `serve`, waveforms — sits above this module.

pub mod aot;
pub mod pipeline;
pub mod scenario;
pub mod watch;
pub mod waveform;

use ladder_front::host_device::HostDevice;
use ladder_front::program::CheckedProgram;
use ladder_interp::Interpreter;
use ladder_runtime::calendar::CalendarTime;
use ladder_runtime::{BitArea, Memory};

/// The engines `ladderc test` and `ladderc run` know.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum EngineKind {
    Interp,
    Jit,
    Aot,
    /// The C back end's source compiled by the system's C compiler (-O2)
    /// into the same host process as `Aot`.
    C,
    /// The firmware route: the same with a compact image (`--image
    /// compact`: the devices the program uses and those the host names, a
    /// scenario's) and the timers and counters of a microcontroller target
    /// (calls of the runtime, `ladder_ir::Coils::Calls`).
    CCompact,
}

impl EngineKind {
    pub const ALL: [EngineKind; 5] = [
        EngineKind::Interp,
        EngineKind::Jit,
        EngineKind::Aot,
        EngineKind::C,
        EngineKind::CCompact,
    ];

    pub fn name(self) -> &'static str {
        match self {
            EngineKind::Interp => "interp",
            EngineKind::Jit => "jit",
            EngineKind::Aot => "aot",
            EngineKind::C => "c",
            EngineKind::CCompact => "c-compact",
        }
    }
}

/// Why an engine could not be set up for a program.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum EngineError {
    /// The engine cannot run on this machine (reported as skipped, never as
    /// passed).
    Unavailable(String),
    /// The engine failed on this program (a failure of the scenario).
    Failed(String),
}

/// What a scenario needs from an engine.
pub trait Engine {
    fn read(&mut self, device: HostDevice) -> Result<i32, String>;
    fn write(&mut self, device: HostDevice, value: i32) -> Result<(), String>;
    fn force(&mut self, area: BitArea, index: u32, on: bool) -> Result<(), String>;
    fn unforce(&mut self, area: BitArea, index: u32) -> Result<(), String>;
    /// One whole scan reporting `elapsed_ms`.
    fn scan(&mut self, elapsed_ms: u32) -> Result<(), String>;
    /// `count` rising edges of input X`input` (0-7) before the next scan.
    fn pulse(&mut self, input: u32, count: u32) -> Result<(), String>;
    /// Sets the calendar clock.
    fn set_clock(&mut self, time: CalendarTime) -> Result<(), String>;
    /// The device image, for engines that hold it in this process.
    fn image(&self) -> Option<&Memory> {
        None
    }
    /// The input refresh without a scan (a CPU in STOP): X takes the
    /// inputs written since the last scan. Engines that hold no image here
    /// refresh at their next scan.
    fn refresh_inputs(&mut self) {}
    /// Replaces the device image (online change); false when the engine
    /// does not hold one in this process.
    fn load_image(&mut self, _image: &Memory) -> bool {
        false
    }
}

/// Something that runs step 3 of the scan on a memory image.
pub trait ProgramRunner {
    fn run_program(&self, mem: &mut Memory);
}

impl ProgramRunner for Interpreter<'_> {
    fn run_program(&self, mem: &mut Memory) {
        Interpreter::run_program(self, mem);
    }
}

impl ProgramRunner for ladder_codegen::JitProgram {
    fn run_program(&self, mem: &mut Memory) {
        self.run(mem);
    }
}

/// An engine that runs in this process on its own memory image.
pub struct InProcess<R> {
    pub memory: Box<Memory>,
    pub runner: R,
}

impl<R: ProgramRunner> InProcess<R> {
    pub fn new(runner: R) -> InProcess<R> {
        InProcess {
            memory: Memory::new_boxed(),
            runner,
        }
    }
}

impl<R: ProgramRunner> Engine for InProcess<R> {
    fn read(&mut self, device: HostDevice) -> Result<i32, String> {
        self.memory
            .read_device(device.device, device.width)
            .ok_or_else(|| format!("cannot read {:?}", device.device))
    }

    fn write(&mut self, device: HostDevice, value: i32) -> Result<(), String> {
        self.memory
            .write_device(device.device, device.width, value)
            .then_some(())
            .ok_or_else(|| format!("cannot write {:?}", device.device))
    }

    fn force(&mut self, area: BitArea, index: u32, on: bool) -> Result<(), String> {
        self.memory.force(area, index, on).map_err(|e| e.to_string())
    }

    fn unforce(&mut self, area: BitArea, index: u32) -> Result<(), String> {
        self.memory.unforce(area, index).map_err(|e| e.to_string())
    }

    fn scan(&mut self, elapsed_ms: u32) -> Result<(), String> {
        let runner = &self.runner;
        self.memory.scan_with(elapsed_ms, |mem| runner.run_program(mem));
        Ok(())
    }

    fn pulse(&mut self, input: u32, count: u32) -> Result<(), String> {
        self.memory
            .add_pulses(input, count)
            .then_some(())
            .ok_or_else(|| format!("X{input:o} does not feed a high-speed counter"))
    }

    fn set_clock(&mut self, time: CalendarTime) -> Result<(), String> {
        self.memory
            .set_calendar(time)
            .then_some(())
            .ok_or_else(|| format!("{time:?} is not a time the clock can show"))
    }

    fn image(&self) -> Option<&Memory> {
        Some(&self.memory)
    }

    fn refresh_inputs(&mut self) {
        self.memory.image().refresh_inputs();
    }

    fn load_image(&mut self, image: &Memory) -> bool {
        *self.memory = *image;
        true
    }
}

/// Builds an engine for a checked program whose host reads and writes
/// `host_devices` (a compact image holds them; the other engines hold
/// every device). Compiled programs keep up to date the parts of the
/// machine that the program and those devices use (`image::machine_use`);
/// in-process engines keep all of them.
pub fn instantiate<'p>(
    kind: EngineKind,
    program: &'p CheckedProgram,
    host_devices: &[HostDevice],
) -> Result<Box<dyn Engine + 'p>, EngineError> {
    match kind {
        // The interpreter runs the checked program: nothing to lower.
        EngineKind::Interp => Ok(Box::new(InProcess::new(Interpreter::new(program)))),
        EngineKind::Jit | EngineKind::Aot | EngineKind::C | EngineKind::CCompact => {
            instantiate_lowered(kind, &crate::pipeline::Lowered::new(program), host_devices)
        }
    }
}

/// `instantiate` from a program lowered once, so that several engines
/// share one lowering (a scenario on every engine).
pub fn instantiate_lowered<'p>(
    kind: EngineKind,
    lowered: &crate::pipeline::Lowered<'p>,
    host_devices: &[HostDevice],
) -> Result<Box<dyn Engine + 'p>, EngineError> {
    use crate::pipeline::ImageRequest;
    match kind {
        EngineKind::Interp => Ok(Box::new(InProcess::new(Interpreter::new(lowered.checked())))),
        EngineKind::Jit => {
            let compiled = lowered.jit().map_err(|e| EngineError::Failed(e.to_string()))?;
            Ok(Box::new(InProcess::new(compiled)))
        }
        EngineKind::Aot => Ok(Box::new(crate::aot::AotEngine::start(
            lowered,
            crate::aot::Route::Object,
            &ImageRequest::full_with(host_devices.to_vec()),
        )?)),
        EngineKind::C => Ok(Box::new(crate::aot::AotEngine::start(
            lowered,
            crate::aot::Route::C,
            &ImageRequest::full_with(host_devices.to_vec()),
        )?)),
        // The firmware route: a compact image, and the timer and counter
        // coils a microcontroller gets (calls of the runtime), so that
        // every scenario runs them as well as the inline ones.
        EngineKind::CCompact => Ok(Box::new(crate::aot::AotEngine::start(
            &crate::pipeline::Lowered::with_coils(lowered.checked(), ladder_ir::Coils::Calls),
            crate::aot::Route::C,
            &ImageRequest::compact(host_devices.to_vec()),
        )?)),
    }
}
