//! The yardstick: the same bit-logic program as ladderc IL (JIT) and as the
//! C an IL→C translator writes (matiec/OpenPLC, LDmicro), compiled with the
//! system `cc -O2`. Reports native scan time next to the C scan time at 11k
//! and 100k instructions; read the ratio within one run.
//!
//! Skipped with a message when there is no C compiler.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use ladder_runtime::Memory;
use ladderc::check::compile_source;
use ladderc::source::SourceFile;
use ladderc_benches::{bit_logic, BitLogic, BIT_LOGIC_RELAYS};
use std::hint::black_box;
use std::path::{Path, PathBuf};
use std::process::Command;

/// `struct image` of the generated C.
#[repr(C)]
struct CImage {
    x: [u8; 256],
    y: [u8; 256],
    m: [u8; BIT_LOGIC_RELAYS as usize],
}

type CScan = unsafe extern "C" fn(*mut CImage);

/// Compiles the C to a shared library in the target folder (kept between
/// runs by content), or says why it cannot.
fn compile_c(program: &BitLogic) -> Result<PathBuf, String> {
    let folder = Path::new(env!("CARGO_MANIFEST_DIR")).join("../target/c-route");
    std::fs::create_dir_all(&folder).map_err(|e| e.to_string())?;
    let digest = program.c.bytes().fold(0xcbf2_9ce4_8422_2325u64, |h, b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
    });
    let library = folder.join(format!("scan-{digest:016x}.so"));
    if library.exists() {
        return Ok(library);
    }
    let source = folder.join(format!("scan-{digest:016x}.c"));
    std::fs::write(&source, &program.c).map_err(|e| e.to_string())?;
    let compiler = std::env::var("CC").unwrap_or_else(|_| "cc".into());
    let status = Command::new(&compiler)
        .args(["-O2", "-shared", "-fPIC", "-o"])
        .arg(&library)
        .arg(&source)
        .status()
        .map_err(|e| format!("cannot run `{compiler}`: {e}"))?;
    if !status.success() {
        return Err(format!("`{compiler} -O2` failed on {}", source.display()));
    }
    Ok(library)
}

fn set_inputs(x: &mut [u8], scan: u32) {
    let pattern = scan.wrapping_mul(2_654_435_761);
    for (i, input) in x.iter_mut().enumerate() {
        *input = ((pattern >> (i % 29)) & 1) as u8;
    }
}

fn c_route(c: &mut Criterion) {
    let mut group = c.benchmark_group("c_route");
    for (instructions, relays) in [(11_000, 1024), (11_000, 64), (100_000, 1024), (100_000, 64)] {
        let program = bit_logic(instructions, relays, 1);
        let (checked, diagnostics) = compile_source(&SourceFile::new("bit_logic.il", program.il.as_str()));
        let checked = checked.unwrap_or_else(|| panic!("{diagnostics:?}"));
        let jit = ladderc::pipeline::jit(&checked).expect("compiles");
        let library = match compile_c(&program) {
            Ok(library) => library,
            Err(why) => {
                eprintln!("c_route: skipped, no C compiler to compare with: {why}");
                return;
            }
        };
        // SAFETY: the library is the one just compiled from our own C, and
        // `scan` has the declared signature.
        let library = unsafe { libloading::Library::new(&library) }.expect("loads the compiled C");
        let c_scan: CScan = *unsafe { library.get::<CScan>(b"scan") }.expect("exports scan");

        // Same scans on both sides must leave the same Y and M.
        let mut mem = Memory::new_boxed();
        let mut image = Box::new(CImage {
            x: [0; 256],
            y: [0; 256],
            m: [0; BIT_LOGIC_RELAYS as usize],
        });
        for scan in 0..50 {
            set_inputs(&mut mem.x[..256], scan);
            set_inputs(&mut image.x, scan);
            jit.run(&mut mem);
            // SAFETY: a valid, exclusive image.
            unsafe { c_scan(&mut *image) };
        }
        assert_eq!(&mem.y[..256], &image.y[..], "Y differs between ladderc and C");
        assert_eq!(
            &mem.m[..BIT_LOGIC_RELAYS as usize],
            &image.m[..],
            "M differs between ladderc and C"
        );

        let label = format!("{}_instructions_{relays}_relays", program.instructions);
        let mut scan = 0u32;
        group.bench_function(BenchmarkId::new("ladderc_jit", &label), |b| {
            b.iter(|| {
                scan = scan.wrapping_add(1);
                mem.x[0] = (scan & 1) as u8;
                jit.run(black_box(&mut mem));
            })
        });
        group.bench_function(BenchmarkId::new("gcc_O2", &label), |b| {
            b.iter(|| {
                scan = scan.wrapping_add(1);
                image.x[0] = (scan & 1) as u8;
                // SAFETY: as above.
                unsafe { c_scan(black_box(&mut *image)) };
            })
        });
    }
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().warm_up_time(std::time::Duration::from_secs(1)).measurement_time(std::time::Duration::from_secs(3));
    targets = c_route
}
criterion_main!(benches);
