//! What a whole scan costs on the native routes, as a firmware host calls
//! it (`<prefix>scan(image, elapsed_ms)`: the runtime's steps before and
//! after the program, and the program), read as ratios within one run:
//!
//! - the fixed cost: a two-instruction program (`LD X0 / OUT Y0`) against
//!   11,000 instructions of bit logic, both Cranelift objects;
//! - 11,000 instructions of bit logic: Cranelift's object against the C an
//!   IL→C translator writes for it (one byte per bit in globals, as LDmicro
//!   and OpenPLC's matiec do), compiled with the system's `cc -O2`;
//! - the mixed plant of 200 machine units (timers, counters, arithmetic,
//!   comparisons, edges, STL): Cranelift's object against ladderc's own C
//!   route (`--emit c`) at `cc -O2`.
//!
//! Each program is linked into a shared library with the runtime library
//! (calls bound inside it, as a static link binds them); the routes must
//! leave the same devices before they are timed. The ratios are printed
//! last, next to the marks they should meet: from criterion's estimates of
//! this run, and from CPU time measured in paired rounds after it
//! (`ladderc_benches::paired`), which the marks are judged by.
//!
//! Skipped with a message when there is no C compiler or runtime library.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use ladder_codegen::ObjectOptions;
use ladder_engine::pipeline::ImageRequest;
use ladder_front::check::compile_source;
use ladder_front::program::CheckedProgram;
use ladder_front::source::SourceFile;
use ladder_runtime::Memory;
use ladderc_benches::paired::{paired_cpu_ratio, PairedRatio};
use std::hint::black_box;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, SystemTime};

type Scan = unsafe extern "C" fn(*mut Memory, u32);
type Init = unsafe extern "C" fn(*mut u8, usize) -> *mut u8;
type NaiveScan = unsafe extern "C" fn();
type NaiveArea = unsafe extern "C" fn() -> *mut u8;

const GROUP: &str = "scan_cost";
const PREFIX: &str = "bench_";

fn folder() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../target/scan-cost")
}

/// Links `inputs` (objects and C files) with the runtime into a shared
/// library `name`.so at `cc -O2`.
fn shared_library(name: &str, inputs: &[PathBuf], with_runtime: bool) -> Result<PathBuf, String> {
    let compiler = ladder_engine::aot::toolchain::c_compiler()?;
    let library = folder().join(format!("{name}.so"));
    let mut command = Command::new(&compiler);
    command
        .args(["-std=c99", "-O2", "-shared", "-fPIC", "-Wl,-Bsymbolic-functions"])
        .arg("-I")
        .arg(folder())
        .arg("-o")
        .arg(&library)
        .args(inputs);
    if with_runtime {
        command
            .arg(ladder_engine::aot::toolchain::runtime_library()?)
            .args(ladder_engine::aot::toolchain::NATIVE_LIBS);
    }
    let output = command.output().map_err(|e| format!("cannot run `{compiler}`: {e}"))?;
    if !output.status.success() {
        return Err(format!(
            "`{compiler} -O2` failed on {name}: {}",
            String::from_utf8_lossy(&output.stderr)
        ));
    }
    Ok(library)
}

/// A route's whole scan, loaded.
struct Route {
    _library: libloading::Library,
    scan: Scan,
    init: Init,
}

impl Route {
    fn load(library: &Path) -> Route {
        // SAFETY: the library was just built from ladderc's output with the
        // runtime; its entry points have the declared signatures.
        unsafe {
            let library = libloading::Library::new(library).expect("loads the built program");
            let scan = *library.get::<Scan>(b"bench_scan").expect("exports bench_scan");
            let init = *library.get::<Init>(b"bench_init").expect("exports bench_init");
            Route {
                _library: library,
                scan,
                init,
            }
        }
    }

    fn image(&self) -> Box<Memory> {
        let mut mem = Memory::new_boxed();
        let size = std::mem::size_of::<Memory>();
        // SAFETY: writable storage of the full image's size and alignment.
        let image = unsafe { (self.init)((&mut *mem as *mut Memory).cast(), size) };
        assert!(!image.is_null(), "the image was refused");
        mem
    }

    fn scan(&self, mem: &mut Memory, elapsed_ms: u32) {
        // SAFETY: `mem` is an image `init` initialised, used by one caller.
        unsafe { (self.scan)(mem, elapsed_ms) }
    }

    /// Scans of `mem` as the benches time them: X0 toggles between scans.
    fn scanner<'a>(&'a self, mem: &'a mut Memory) -> impl FnMut() + 'a {
        let mut scans = 0u32;
        move || {
            scans = scans.wrapping_add(1);
            mem.input_image[0] = (scans & 1) as u8;
            self.scan(black_box(&mut *mem), 10);
        }
    }
}

fn checked(name: &str, text: &str) -> CheckedProgram {
    let (checked, diagnostics) = compile_source(&SourceFile::new(format!("{name}.il"), text));
    checked.unwrap_or_else(|| panic!("{name}: {diagnostics:?}"))
}

/// The Cranelift object of `program` (full image), as a shared library.
fn cranelift(name: &str, program: &CheckedProgram) -> Result<Route, String> {
    let options = ObjectOptions {
        prefix: PREFIX.to_string(),
        ..ObjectOptions::default()
    };
    let object = ladder_engine::pipeline::Lowered::new(program)
        .object(&options, &ImageRequest::full())
        .map_err(|e| e.to_string())?
        .output;
    let path = folder().join(format!("{name}_cranelift.o"));
    std::fs::write(&path, object).map_err(|e| e.to_string())?;
    Ok(Route::load(&shared_library(
        &format!("{name}_cranelift"),
        &[path],
        true,
    )?))
}

/// ladderc's C route of `program` (full image), as a shared library.
fn c_route(name: &str, program: &CheckedProgram) -> Result<Route, String> {
    let options = ladder_cback::COptions {
        prefix: PREFIX.to_string(),
        source_name: name.to_string(),
        layout: None,
        ..Default::default()
    };
    let source = ladder_engine::pipeline::Lowered::new(program)
        .c_source(&options, &ImageRequest::full())
        .output;
    let path = folder().join(format!("{name}_c_route.c"));
    std::fs::write(&path, source).map_err(|e| e.to_string())?;
    Ok(Route::load(&shared_library(&format!("{name}_c_route"), &[path], true)?))
}

/// The naive translation's scan and its three areas.
struct Naive {
    _library: libloading::Library,
    scan: NaiveScan,
    x: *mut u8,
    y: *mut u8,
    m: *mut u8,
}

fn naive(name: &str, c: &str) -> Result<Naive, String> {
    let path = folder().join(format!("{name}_naive.c"));
    std::fs::write(&path, c).map_err(|e| e.to_string())?;
    let library = shared_library(&format!("{name}_naive"), &[path], false)?;
    // SAFETY: the library was just built from the bench's own C, whose
    // functions have the declared signatures.
    unsafe {
        let library = libloading::Library::new(library).expect("loads the naive C");
        let scan = *library.get::<NaiveScan>(b"scan").expect("exports scan");
        let area = |symbol: &[u8]| library.get::<NaiveArea>(symbol).expect("exports its areas")();
        let (x, y, m) = (area(b"image_x"), area(b"image_y"), area(b"image_m"));
        Ok(Naive {
            scan,
            x,
            y,
            m,
            _library: library,
        })
    }
}

fn pattern(scan: u32, i: usize) -> u8 {
    ((scan.wrapping_mul(2_654_435_761) >> (i % 29)) & 1) as u8
}

fn skip(why: String) {
    eprintln!("{GROUP}: skipped: {why}");
}

fn scan_cost(c: &mut Criterion) {
    let run_start = SystemTime::now();
    if let Err(why) = std::fs::create_dir_all(folder()) {
        return skip(why.to_string());
    }
    let mut group = c.benchmark_group(GROUP);

    // The fixed cost of a scan: a program that uses nothing of the machine.
    let two = checked("two_instructions", "LD X0\nOUT Y0\n");
    let two = match cranelift("two_instructions", &two) {
        Ok(route) => route,
        Err(why) => return skip(why),
    };
    let mut two_mem = two.image();
    let mut scan_two = two.scanner(&mut two_mem);
    group.bench_function(BenchmarkId::new("cranelift", "two_instructions"), |b| {
        b.iter(&mut scan_two)
    });

    // 11k bit logic: Cranelift against the naive C translation.
    let logic = ladderc_benches::bit_logic(11_000, ladderc_benches::BIT_LOGIC_RELAYS, 1);
    let program = checked("bit_logic_11k", &logic.il);
    let (object, naive) = match (cranelift("bit_logic_11k", &program), naive("bit_logic_11k", &logic.c)) {
        (Ok(object), Ok(naive)) => (object, naive),
        (Err(why), _) | (_, Err(why)) => return skip(why),
    };
    let mut mem = object.image();
    for scan in 0..50 {
        for (i, input) in mem.input_image[..256].iter_mut().enumerate() {
            *input = pattern(scan, i);
        }
        object.scan(&mut mem, 10);
        // SAFETY: the naive C's areas have 256, 256 and 1024 bytes; its
        // scan touches only them.
        unsafe {
            for i in 0..256 {
                *naive.x.add(i) = pattern(scan, i);
            }
            (naive.scan)();
        }
    }
    let relays = ladderc_benches::BIT_LOGIC_RELAYS as usize;
    // SAFETY: as above.
    let (naive_y, naive_m) = unsafe {
        (
            std::slice::from_raw_parts(naive.y, 256),
            std::slice::from_raw_parts(naive.m, relays),
        )
    };
    assert_eq!(&mem.y[..256], naive_y, "Y differs between ladderc and the naive C");
    assert_eq!(&mem.m[..relays], naive_m, "M differs between ladderc and the naive C");
    let mut scan_logic = object.scanner(&mut mem);
    let mut naive_scans = 0u32;
    let mut scan_naive = || {
        naive_scans = naive_scans.wrapping_add(1);
        // SAFETY: as above.
        unsafe {
            *naive.x = (naive_scans & 1) as u8;
            (naive.scan)();
        }
    };
    group.bench_function(BenchmarkId::new("cranelift", "bit_logic_11k"), |b| {
        b.iter(&mut scan_logic)
    });
    group.bench_function(BenchmarkId::new("naive_c_gcc_O2", "bit_logic_11k"), |b| {
        b.iter(&mut scan_naive)
    });

    // The mixed plant: Cranelift against ladderc's own C route.
    let program = checked("plant_200", &ladderc_benches::plant(200));
    let (plant_object, c) = match (cranelift("plant_200", &program), c_route("plant_200", &program)) {
        (Ok(plant_object), Ok(c)) => (plant_object, c),
        (Err(why), _) | (_, Err(why)) => return skip(why),
    };
    let (mut object_mem, mut c_mem) = (plant_object.image(), c.image());
    for scan in 0..200 {
        for mem in [&mut object_mem, &mut c_mem] {
            for (i, input) in mem.input_image[..256].iter_mut().enumerate() {
                *input = pattern(scan, i);
            }
        }
        plant_object.scan(&mut object_mem, 10);
        c.scan(&mut c_mem, 10);
    }
    assert!(
        bytemuck::bytes_of(&*object_mem) == bytemuck::bytes_of(&*c_mem),
        "plant_200: the C route left another image than Cranelift"
    );
    let mut scan_plant = plant_object.scanner(&mut object_mem);
    let mut scan_c_route = c.scanner(&mut c_mem);
    group.bench_function(BenchmarkId::new("cranelift", "plant_200"), |b| b.iter(&mut scan_plant));
    group.bench_function(BenchmarkId::new("c_route_gcc_O2", "plant_200"), |b| {
        b.iter(&mut scan_c_route)
    });
    group.finish();

    // The same pairs again, timed in alternating rounds (`paired.rs`);
    // not when criterion only checks that the benches run.
    if std::env::args().any(|arg| arg == "--test" || arg == "--list") {
        return;
    }
    let paired = [
        paired_cpu_ratio(&mut scan_two, &mut scan_logic, PAIRED_ROUNDS, PAIRED_ROUND_TIME),
        paired_cpu_ratio(&mut scan_logic, &mut scan_naive, PAIRED_ROUNDS, PAIRED_ROUND_TIME),
        paired_cpu_ratio(&mut scan_plant, &mut scan_c_route, PAIRED_ROUNDS, PAIRED_ROUND_TIME),
    ];
    report_ratios(paired, run_start);
}

/// Criterion's estimate of the mean time of `route` on `program` in this
/// run (written after `run_start`), in nanoseconds.
fn estimate(route: &str, program: &str, run_start: SystemTime) -> Option<f64> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../target/criterion")
        .join(GROUP)
        .join(route)
        .join(program)
        .join("new/estimates.json");
    if std::fs::metadata(&path).ok()?.modified().ok()? < run_start {
        return None;
    }
    let json: serde_json::Value = serde_json::from_slice(&std::fs::read(path).ok()?).ok()?;
    json["mean"]["point_estimate"].as_f64()
}

/// Paired rounds per ratio, and the CPU time of each side in a round: 25
/// rounds of 2 × 25 ms, under two seconds a ratio.
const PAIRED_ROUNDS: usize = 25;
const PAIRED_ROUND_TIME: Duration = Duration::from_millis(25);

/// Prints each ratio twice: from criterion's estimates, and from the
/// paired rounds, which decide whether the mark is met (criterion times
/// one side seconds after the other; `paired.rs` says why that matters).
fn report_ratios(paired: [Option<PairedRatio>; 3], run_start: SystemTime) {
    let ratios = [
        (
            "fixed cost: two instructions / 11k bit logic (Cranelift)",
            ("cranelift", "two_instructions"),
            ("cranelift", "bit_logic_11k"),
            0.03,
        ),
        (
            "11k bit logic: Cranelift / naive C at gcc -O2",
            ("cranelift", "bit_logic_11k"),
            ("naive_c_gcc_O2", "bit_logic_11k"),
            0.80,
        ),
        (
            "plant of 200 units: Cranelift / ladderc's C route at gcc -O2",
            ("cranelift", "plant_200"),
            ("c_route_gcc_O2", "plant_200"),
            0.90,
        ),
    ];
    eprintln!("\n{GROUP}: ratios of this run (mark in brackets)");
    for ((what, (a_route, a_program), (b_route, b_program), mark), paired) in ratios.into_iter().zip(paired) {
        eprintln!("  {what} [<= {mark}]");
        match (
            estimate(a_route, a_program, run_start),
            estimate(b_route, b_program, run_start),
        ) {
            (Some(a), Some(b)) => eprintln!("    criterion's means: {:.3} ({a:.1} ns / {b:.1} ns)", a / b),
            _ => eprintln!("    criterion's means: none from this run (a filtered run?)"),
        }
        match paired {
            Some(ratio) => eprintln!(
                "    CPU time, median of {} paired rounds: {:.3} (middle half {:.3}-{:.3}){}",
                ratio.rounds,
                ratio.median,
                ratio.lower_quartile,
                ratio.upper_quartile,
                if ratio.median <= mark {
                    ""
                } else {
                    "  -- above the mark"
                }
            ),
            None => eprintln!("    CPU time: no round measured any time"),
        }
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default().warm_up_time(std::time::Duration::from_secs(1)).measurement_time(std::time::Duration::from_secs(3));
    targets = scan_cost
}
criterion_main!(benches);
