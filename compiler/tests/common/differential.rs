//! The differential test's engine room: a random case is a generated program
//! and the host calls and times of each scan; it runs on the interpreter (the
//! specification), the JIT, and — in batches of programs linked into one C
//! host — the object-file path, and the whole device image of every engine
//! must equal the interpreter's after every scan. A divergence is shrunk to
//! a small case and written out as a scenario file.

use super::image::{self, Difference};
use super::stimulus::{self, Step};
use ladder_codegen::ObjectOptions;
use ladder_engine::pipeline::{ImageRequest, Lowered};
use ladder_front::check::compile_source;
use ladder_front::diagnostics::render_all;
use ladder_front::program::CheckedProgram;
use ladder_front::source::SourceFile;
use ladder_interp::Interpreter;
use ladder_runtime::Memory;
use proptest::prelude::*;
use proptest::strategy::ValueTree;
use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

/// A program and what the host does around each of its scans.
#[derive(Clone, Debug)]
pub struct Case {
    pub program: String,
    pub steps: Vec<Step>,
}

pub fn case(program: impl Strategy<Value = String>) -> impl Strategy<Value = Case> {
    (program, proptest::collection::vec(stimulus::step(), 1..25)).prop_map(|(program, steps)| Case { program, steps })
}

/// Where an engine first left the interpreter.
#[derive(Clone, Debug)]
pub struct Divergence {
    pub engine: &'static str,
    /// 0-based index of the scan after which the images differ.
    pub scan: usize,
    /// The differing elements (empty when only a digest is known).
    pub differences: Vec<Difference>,
}

/// Counts of one run, for the report.
#[derive(Clone, Copy, Debug, Default)]
pub struct Totals {
    pub programs: usize,
    pub scans: usize,
    /// Programs also run on the object-file path.
    pub aot_programs: usize,
    /// Programs also run on the C route (C back end, gcc -O2).
    pub c_programs: usize,
    /// Programs also run on the C route with a compact image.
    pub compact_programs: usize,
}

pub fn compile(text: &str) -> CheckedProgram {
    let file = SourceFile::new("gen.il", text);
    let (program, diagnostics) = compile_source(&file);
    program.unwrap_or_else(|| {
        panic!(
            "generated program rejected:\n{text}\n{}",
            render_all(&file, &diagnostics, ladder_front::diagnostics::Shown::All)
        )
    })
}

/// The parts of the machine the scans of `case` keep up to date, on every
/// engine: those its program and its host's devices use, as a compiled
/// program's scan keeps them (whole images are compared, so the in-process
/// engines keep the same).
pub fn machine(case: &Case, lowered: &Lowered) -> ladder_runtime::MachineUse {
    ladder_ir::image::machine_use(lowered.checked(), lowered.ir(), &host_devices(case))
}

/// Runs `case` on the interpreter and the JIT, comparing whole images after
/// every scan; returns the interpreter's image digests.
pub fn in_process(case: &Case, lowered: &Lowered) -> Result<Vec<u64>, Divergence> {
    let jit = lowered.jit().expect("generated programs compile to native code");
    let interpreter = Interpreter::new(lowered.checked());
    let machine = machine(case, lowered);
    let mut expected = Memory::new_boxed();
    let mut actual = Memory::new_boxed();
    let mut digests = Vec::with_capacity(case.steps.len());
    for (scan, step) in case.steps.iter().enumerate() {
        stimulus::apply(&mut expected, step);
        stimulus::apply(&mut actual, step);
        interpreter.scan_using(&mut expected, step.elapsed_ms, machine);
        actual.scan_using(step.elapsed_ms, machine, |mem| jit.run(mem));
        if bytemuck::bytes_of(&*expected) != bytemuck::bytes_of(&*actual) {
            return Err(Divergence {
                engine: "jit",
                scan,
                differences: image::differences(&expected, &actual),
            });
        }
        digests.push(image::digest(&expected));
    }
    Ok(digests)
}

/// The interpreter's image after `scans` scans of `case`.
pub fn interpreter_image(case: &Case, lowered: &Lowered, scans: usize) -> Box<Memory> {
    let interpreter = Interpreter::new(lowered.checked());
    let machine = machine(case, lowered);
    let mut mem = Memory::new_boxed();
    for step in &case.steps[..scans] {
        stimulus::apply(&mut mem, step);
        interpreter.scan_using(&mut mem, step.elapsed_ms, machine);
    }
    mem
}

/// How a native engine gets the program into the driver.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Route {
    /// Cranelift's object file.
    Object,
    /// The C back end's source, compiled by the system's C compiler at -O2
    /// with every warning an error.
    C,
    /// The same with a compact image (`--image compact`, the host devices
    /// being those the case's host calls name): every device the image
    /// holds must equal the interpreter's.
    CompactC,
}

/// The devices a case's host calls name: a compact image holds them.
pub fn host_devices(case: &Case) -> Vec<ladder_front::host_device::HostDevice> {
    use ladder_runtime::capi::{basic_device, LadderDevice};
    use ladder_runtime::{Basic, BitArea, Device, Width};
    use stimulus::HostAction;
    let device = |kind: LadderDevice, n: u32| {
        let device = match basic_device(kind as u32, n)? {
            Basic::Bit(area, n) => Device::Bit(area, n),
            Basic::Word(area, n) => Device::Word(area, n),
            Basic::WideCounter(n) => Device::WideCounter(n),
        };
        Some(ladder_front::host_device::HostDevice {
            device,
            width: Width::Single,
        })
    };
    case.steps
        .iter()
        .flat_map(|step| &step.actions)
        .filter_map(|action| match *action {
            HostAction::Input(x, _) | HostAction::Pulses(x, _) => device(LadderDevice::X, x),
            HostAction::Write(kind, n, _) | HostAction::Force(kind, n, _) | HostAction::Unforce(kind, n) => {
                device(kind, n)
            }
            HostAction::WriteWordBit(n, _, _) => device(LadderDevice::D, n),
        })
        .filter(|d| !matches!(d.device, Device::Bit(BitArea::X, n) if n >= 256))
        .collect()
}

/// The compact layout of `program` for `case`'s host.
pub fn compact_layout(case: &Case, lowered: &Lowered) -> ladder_runtime::layout::Layout {
    ImageRequest::compact(host_devices(case))
        .layout(lowered.checked(), lowered.ir())
        .expect("a compact layout")
}

/// The interpreter's digests of `case` as a compact image of `program`
/// would hold them.
pub fn compact_digests(case: &Case, lowered: &Lowered) -> Vec<u64> {
    let layout = compact_layout(case, lowered);
    let interpreter = Interpreter::new(lowered.checked());
    let machine = machine(case, lowered);
    let mut mem = Memory::new_boxed();
    case.steps
        .iter()
        .map(|step| {
            stimulus::apply(&mut mem, step);
            interpreter.scan_using(&mut mem, step.elapsed_ms, machine);
            image::digest_bytes(&image::project(&mem, &layout))
        })
        .collect()
}

/// A native engine outside the process: programs compiled with their own
/// prefixes and linked with the runtime library into the differential
/// driver.
pub struct AotHost {
    route: Route,
    compiler: String,
    library: PathBuf,
    /// Extra linker arguments the library needs.
    libraries: Vec<String>,
}

impl AotHost {
    /// The firmware library when it builds, else the library cargo built
    /// for ladderc; `Err` says why neither can be used.
    pub fn find(route: Route) -> Result<AotHost, String> {
        let compiler = ladder_engine::aot::toolchain::c_compiler()?;
        let (library, libraries) = match super::tools::firmware_runtime_library() {
            Ok(library) => (library, vec!["-nodefaultlibs".to_string(), "-lc".to_string()]),
            Err(why) => {
                eprintln!("differential aot: using the std runtime library ({why})");
                let libs = ladder_engine::aot::toolchain::NATIVE_LIBS
                    .iter()
                    .map(|s| s.to_string())
                    .collect();
                (ladder_engine::aot::toolchain::runtime_library()?, libs)
            }
        };
        Ok(AotHost {
            route,
            compiler,
            library,
            libraries,
        })
    }

    /// Builds one driver for the programs of `cases` in `work`.
    fn link(&self, cases: &[(&Case, &Lowered)], work: &Path) -> Result<PathBuf, String> {
        let mut sources = vec![super::tools::workspace().join("testsuite/differential/driver.c")];
        let mut list = String::from("#define PROGRAMS");
        let mut c_sources = Vec::new();
        for (i, (case, lowered)) in cases.iter().enumerate() {
            let prefix = format!("p{i}_");
            match self.route {
                Route::Object => {
                    let options = ObjectOptions {
                        target: None,
                        prefix: prefix.clone(),
                        layout: None,
                        ..Default::default()
                    };
                    let image = ImageRequest::full_with(host_devices(case));
                    let object = lowered.object(&options, &image).map_err(|e| e.to_string())?.output;
                    let path = work.join(format!("p{i}.o"));
                    std::fs::write(&path, object).map_err(|e| e.to_string())?;
                    sources.push(path);
                }
                Route::C | Route::CompactC => {
                    let options = ladder_cback::COptions {
                        prefix: prefix.clone(),
                        source_name: format!("p{i}.il"),
                        layout: None,
                        ..Default::default()
                    };
                    // The compact route is the firmware's: its timers and
                    // counters call the runtime.
                    let (image, coils) = match self.route {
                        Route::CompactC => (ImageRequest::compact(host_devices(case)), ladder_ir::Coils::Calls),
                        Route::Object | Route::C => {
                            (ImageRequest::full_with(host_devices(case)), ladder_ir::Coils::Inline)
                        }
                    };
                    let path = work.join(format!("p{i}.c"));
                    let source = match coils {
                        ladder_ir::Coils::Inline => lowered.c_source(&options, &image).output,
                        ladder_ir::Coils::Calls => {
                            Lowered::with_coils(lowered.checked(), coils)
                                .c_source(&options, &image)
                                .output
                        }
                    };
                    std::fs::write(&path, source).map_err(|e| e.to_string())?;
                    c_sources.push(path);
                    sources.push(work.join(format!("p{i}.o")));
                }
            }
            let _ = write!(list, " X({prefix})");
        }
        if !c_sources.is_empty() {
            // The generated C as a user builds it: -O2, every warning an error.
            let output = Command::new(&self.compiler)
                .current_dir(work)
                .args(["-std=c99", "-O2", "-Wall", "-Wextra", "-Werror", "-c"])
                .args(&c_sources)
                .output()
                .map_err(|e| format!("{} did not run: {e}", self.compiler))?;
            if !output.status.success() {
                return Err(format!(
                    "compiling the generated C failed:\n{}",
                    String::from_utf8_lossy(&output.stderr)
                ));
            }
        }
        std::fs::write(work.join("programs.h"), list + "\n").map_err(|e| e.to_string())?;
        let host = work.join("driver");
        let output = Command::new(&self.compiler)
            .args(["-std=c99", "-O1", "-w"])
            .args(ladder_engine::aot::toolchain::fast_linker(&self.compiler))
            .arg("-I")
            .arg(work)
            .arg("-I")
            .arg(super::tools::workspace().join("runtime/include"))
            .args(&sources)
            .arg(&self.library)
            .args(&self.libraries)
            .arg("-o")
            .arg(&host)
            .output()
            .map_err(|e| format!("{} did not run: {e}", self.compiler))?;
        if !output.status.success() {
            return Err(format!(
                "linking the driver failed:\n{}",
                String::from_utf8_lossy(&output.stderr)
            ));
        }
        Ok(host)
    }

    /// Runs `script` on a driver and returns its output lines.
    fn run(host: &Path, work: &Path, script: &str) -> Result<Vec<String>, String> {
        let script_path = work.join("script.txt");
        std::fs::write(&script_path, script).map_err(|e| e.to_string())?;
        let output = Command::new(host)
            .stdin(std::fs::File::open(&script_path).map_err(|e| e.to_string())?)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .output()
            .map_err(|e| format!("the driver did not run: {e}"))?;
        if !output.status.success() {
            return Err(format!("the driver stopped: {:?}", output.status));
        }
        Ok(String::from_utf8_lossy(&output.stdout)
            .lines()
            .map(str::to_string)
            .collect())
    }

    /// Image digests after every scan of every case, per case.
    pub fn digests(&self, cases: &[(&Case, &Lowered)]) -> Result<Vec<Vec<u64>>, String> {
        let work = tempfile::tempdir().map_err(|e| e.to_string())?;
        let host = self.link(cases, work.path())?;
        let mut script = String::new();
        for (i, (case, _)) in cases.iter().enumerate() {
            let _ = writeln!(script, "P {i}");
            for step in &case.steps {
                stimulus::driver_commands(step, &mut script);
            }
        }
        let lines = Self::run(&host, work.path(), &script)?;
        let mut lines = lines.iter();
        cases
            .iter()
            .map(|(case, _)| {
                case.steps
                    .iter()
                    .map(|_| {
                        let line = lines.next().ok_or("the driver printed too few digests")?;
                        u64::from_str_radix(line, 16).map_err(|e| format!("`{line}`: {e}"))
                    })
                    .collect()
            })
            .collect()
    }

    /// The compiled program's whole image after `scans` scans of `case`
    /// (a compact one expanded: what it does not hold is 0).
    pub fn image(&self, case: &Case, lowered: &Lowered, scans: usize) -> Result<Box<Memory>, String> {
        let work = tempfile::tempdir().map_err(|e| e.to_string())?;
        let host = self.link(&[(case, lowered)], work.path())?;
        let mut script = String::from("P 0\n");
        for step in &case.steps[..scans] {
            stimulus::driver_commands(step, &mut script);
        }
        script.push_str("D\n");
        let lines = Self::run(&host, work.path(), &script)?;
        let hex = lines.last().ok_or("no image printed")?;
        let bytes = (0..hex.len() / 2)
            .map(|i| u8::from_str_radix(&hex[2 * i..2 * i + 2], 16).map_err(|e| e.to_string()))
            .collect::<Result<Vec<u8>, String>>()?;
        match self.route {
            Route::CompactC => Ok(image::expand(&bytes, &compact_layout(case, lowered))),
            Route::Object | Route::C => {
                let mut mem = Memory::new_boxed();
                let full = bytemuck::bytes_of_mut(&mut *mem);
                if bytes.len() != full.len() {
                    return Err(format!("the image has {} bytes", bytes.len()));
                }
                full.copy_from_slice(&bytes);
                Ok(mem)
            }
        }
    }

    /// The interpreter's digests this engine must print for `case`:
    /// `full` for the full image, else those of its compact image.
    fn expected(&self, case: &Case, lowered: &Lowered, full: &[u64]) -> Vec<u64> {
        match self.route {
            Route::Object | Route::C => full.to_vec(),
            Route::CompactC => compact_digests(case, lowered),
        }
    }

    /// The interpreter's image as this engine holds it.
    fn expected_image(&self, case: &Case, lowered: &Lowered, scans: usize) -> Box<Memory> {
        let mem = interpreter_image(case, lowered, scans);
        match self.route {
            Route::Object | Route::C => mem,
            Route::CompactC => {
                let layout = compact_layout(case, lowered);
                image::expand(&image::project(&mem, &layout), &layout)
            }
        }
    }

    /// The engine's name in reports.
    pub fn engine(&self) -> &'static str {
        match self.route {
            Route::Object => "aot",
            Route::C => "c",
            Route::CompactC => "c_compact",
        }
    }

    /// Where this engine leaves the interpreter on `case`, if it does.
    pub fn diverges(&self, case: &Case, lowered: &Lowered, expected: &[u64]) -> Result<Option<usize>, String> {
        let digests = self.digests(&[(case, lowered)])?;
        Ok(first_difference(&self.expected(case, lowered, expected), &digests[0]))
    }
}

pub fn first_difference(expected: &[u64], actual: &[u64]) -> Option<usize> {
    (0..expected.len().max(actual.len())).find(|&i| expected.get(i) != actual.get(i))
}

/// Any engine's divergence on `case` (in-process engines first).
pub fn divergence(case: &Case, hosts: &[AotHost]) -> Option<Divergence> {
    let program = compile(&case.program);
    let lowered = Lowered::new(&program);
    let expected = match in_process(case, &lowered) {
        Ok(digests) => digests,
        Err(divergence) => return Some(divergence),
    };
    hosts.iter().find_map(|host| {
        let scan = host
            .diverges(case, &lowered, &expected)
            .unwrap_or_else(|e| panic!("{}: {e}", host.engine()))?;
        let differences = match host.image(case, &lowered, scan + 1) {
            Ok(actual) => image::differences(&host.expected_image(case, &lowered, scan + 1), &actual),
            Err(_) => Vec::new(),
        };
        Some(Divergence {
            engine: host.engine(),
            scan,
            differences,
        })
    })
}

/// Shrinks the failing `tree` (proptest's simplify/complicate walk) to a
/// case that still diverges, at most `budget` tries.
pub fn minimise(mut tree: impl ValueTree<Value = Case>, hosts: &[AotHost], budget: usize) -> (Case, Divergence) {
    let mut smallest = tree.current();
    let mut found = divergence(&smallest, hosts).expect("the case diverged");
    let mut tries = 0;
    if tree.simplify() {
        while tries < budget {
            tries += 1;
            let candidate = tree.current();
            let failed = std::panic::catch_unwind(|| divergence(&candidate, hosts)).unwrap_or(None);
            if let Some(divergence) = failed {
                smallest = candidate;
                found = divergence;
                if !tree.simplify() {
                    break;
                }
            } else if !tree.complicate() {
                break;
            }
        }
    }
    (smallest, found)
}

/// `case` up to the diverging scan as a scenario whose expectations are the
/// interpreter's values of the devices that differ.
pub fn scenario(case: &Case, divergence: &Divergence) -> String {
    let mut out = format!(
        "# Found by the differential test: {} leaves the interpreter after scan {}.\n",
        divergence.engine,
        divergence.scan + 1
    );
    for difference in divergence.differences.iter().take(20) {
        let _ = writeln!(
            out,
            "# {}: interpreter {}, {} {}",
            difference.place, difference.expected, divergence.engine, difference.actual
        );
    }
    out.push_str("program <<\n");
    out.push_str(&case.program);
    out.push_str(">>\n");
    let mut scan_ms = 10;
    for step in &case.steps[..=divergence.scan] {
        stimulus::scenario_directives(step, &mut scan_ms, &mut out);
    }
    for difference in &divergence.differences {
        if let Some((kind, number)) = difference.device {
            let _ = writeln!(
                out,
                "expect {} {}",
                stimulus::scenario_device(kind, number),
                difference.expected
            );
        }
    }
    out
}

/// Writes `text` under the test's scratch directory; returns the path.
pub fn write_scenario(name: &str, text: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("differential");
    let _ = std::fs::create_dir_all(&dir);
    let path = dir.join(format!("{name}.scn"));
    let _ = std::fs::write(&path, text);
    path
}

/// A runner whose seed is `seed` (reproducible), drawing `case` values.
pub fn runner(seed: u64) -> TestRunner {
    let mut bytes = [0u8; 32];
    bytes[..8].copy_from_slice(&seed.to_le_bytes());
    TestRunner::new_with_rng(Config::default(), TestRng::from_seed(RngAlgorithm::ChaCha, &bytes))
}

/// Runs `count` cases from `seed` on every engine (the engines outside the
/// process in batches of `batch`); panics with the minimised scenario on a
/// divergence.
pub fn check<S>(name: &str, strategy: S, seed: u64, count: usize, batch: usize, hosts: &[AotHost]) -> Totals
where
    S: Strategy<Value = Case>,
{
    let mut runner = runner(seed);
    let mut totals = Totals::default();
    let mut done = 0;
    while done < count {
        let size = batch.min(count - done);
        let mut trees = Vec::with_capacity(size);
        let mut programs = Vec::with_capacity(size);
        for _ in 0..size {
            let tree = strategy.new_tree(&mut runner).expect("a case");
            let case = tree.current();
            let program = compile(&case.program);
            programs.push((case, program));
            trees.push(tree);
        }
        // Each program lowered once, for the JIT and every engine outside
        // the process.
        let lowered: Vec<Lowered> = programs.iter().map(|(_, program)| Lowered::new(program)).collect();
        let mut expected = Vec::with_capacity(size);
        for (i, ((case, _), lowered)) in programs.iter().zip(&lowered).enumerate() {
            match in_process(case, lowered) {
                Ok(digests) => expected.push(digests),
                Err(_) => fail(name, seed, trees.swap_remove(i), hosts),
            }
            totals.programs += 1;
            totals.scans += case.steps.len();
        }
        // The compact image on every other batch: it checks the layout,
        // which the other routes' runs of the same code make no likelier
        // to go wrong, and costs another C build per batch.
        let compact_batch = (done / batch).is_multiple_of(2);
        for host in hosts.iter().filter(|h| h.route != Route::CompactC || compact_batch) {
            let cases: Vec<(&Case, &Lowered)> = programs.iter().map(|(case, _)| case).zip(&lowered).collect();
            let digests = host
                .digests(&cases)
                .unwrap_or_else(|e| panic!("{}: {e}", host.engine()));
            match host.route {
                Route::Object => totals.aot_programs += cases.len(),
                Route::C => totals.c_programs += cases.len(),
                Route::CompactC => totals.compact_programs += cases.len(),
            }
            let diverged = |i: usize| {
                let (case, lowered) = cases[i];
                first_difference(&host.expected(case, lowered, &expected[i]), &digests[i]).is_some()
            };
            if let Some(i) = (0..size).find(|&i| diverged(i)) {
                fail(name, seed, trees.swap_remove(i), hosts);
            }
        }
        done += size;
    }
    totals
}

fn fail(name: &str, seed: u64, tree: impl ValueTree<Value = Case>, hosts: &[AotHost]) -> ! {
    let (case, divergence) = minimise(tree, hosts, 2000);
    let text = scenario(&case, &divergence);
    let path = write_scenario(&format!("{name}-{seed}"), &text);
    panic!(
        "{} differs from the interpreter (seed {seed}); minimised scenario written to {}:\n{text}",
        divergence.engine,
        path.display()
    );
}

/// The seed of this run: `LADDER_DIFFERENTIAL_SEED`, else one fixed per
/// commit and test (the commit's id from git, hashed with the test's name),
/// so a failure in CI happens again on the same commit anywhere; without
/// git, fixed per test.
pub fn seed(test: &str) -> u64 {
    use std::hash::{Hash, Hasher};
    let seed = std::env::var("LADDER_DIFFERENTIAL_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(|| {
            let commit = std::process::Command::new("git")
                .args(["rev-parse", "HEAD"])
                .current_dir(super::tools::workspace())
                .output()
                .ok()
                .filter(|o| o.status.success())
                .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
                .unwrap_or_default();
            // DefaultHasher's algorithm may change between Rust releases;
            // within one toolchain it is fixed, which is what a rerun needs.
            let mut hasher = std::collections::hash_map::DefaultHasher::new();
            (commit, test).hash(&mut hasher);
            hasher.finish()
        });
    eprintln!("{test}: seed {seed} (LADDER_DIFFERENTIAL_SEED={seed} reruns it)");
    seed
}

/// The engines outside the process: the object-file path and the C route
/// (each skipped, with the reason printed, where it cannot be built).
pub fn native_hosts(test: &str) -> Vec<AotHost> {
    [Route::Object, Route::C, Route::CompactC]
        .into_iter()
        .filter_map(|route| match AotHost::find(route) {
            Ok(host) => Some(host),
            Err(why) => {
                super::tools::skip(&format!("{test} ({route:?} engine only)"), &why);
                None
            }
        })
        .collect()
}
