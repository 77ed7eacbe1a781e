//! The two native routes of the same program: the scan body as Cranelift
//! compiles it (the JIT; the object file holds the same code) and as the C
//! back end writes it, compiled by the system's `cc -O2` into a shared
//! library with the runtime. Programs: 11,000 instructions of bit logic and
//! the plant program of 100 machine units (timers, counters, arithmetic,
//! STL). The mark: the C route within 1.2× of Cranelift; read the
//! ratio within one run. Both routes must leave the same image first. The
//! C route also runs with the program's compact image (the runtime then
//! finds devices through the layout table), whose devices must equal the
//! full image's.
//!
//! Skipped with a message when there is no C compiler or runtime library.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use ladder_engine::pipeline::ImageRequest;
use ladder_front::check::compile_source;
use ladder_front::source::SourceFile;
use ladder_runtime::layout::{Array, Layout, SEGMENTS};
use ladder_runtime::{ImageMut, Memory};
use std::hint::black_box;
use std::path::PathBuf;
use std::process::Command;

type Body = unsafe extern "C" fn(*mut Memory);
type CompactBody = unsafe extern "C" fn(*mut u8);
type Init = unsafe extern "C" fn(*mut u8, usize) -> *mut u8;

/// The C of `checked` for an image as `image` asks, with its body exported
/// (the back end keeps it static: hosts call `<prefix>scan`), built into a
/// shared library with the runtime; and the compact layout, if any.
fn c_library(
    name: &str,
    checked: &ladder_front::program::CheckedProgram,
    image: &ImageRequest,
) -> Result<(PathBuf, Option<Layout>), String> {
    let folder = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../target/c-backend");
    std::fs::create_dir_all(&folder).map_err(|e| e.to_string())?;
    let options = ladder_cback::COptions {
        prefix: "bench_".to_string(),
        source_name: name.to_string(),
        layout: None,
        ..Default::default()
    };
    let built = ladder_engine::pipeline::Lowered::new(checked).c_source(&options, image);
    let source = built
        .output
        .replace("static void bench_body(uint8_t *m)", "void bench_body(uint8_t *m)");
    let name = match built.layout {
        Some(_) => format!("{name}_compact"),
        None => name.to_string(),
    };
    let path = folder.join(format!("{name}.c"));
    std::fs::write(&path, source).map_err(|e| e.to_string())?;
    let library = folder.join(format!("{name}.so"));
    let compiler = ladder_engine::aot::toolchain::c_compiler()?;
    let runtime = ladder_engine::aot::toolchain::runtime_library()?;
    let output = Command::new(&compiler)
        // Calls into the runtime bound inside the library, as a static
        // link binds them (a firmware image has no PLT between program and
        // runtime; Cranelift's code calls the helpers directly too).
        .args(["-std=c99", "-O2", "-shared", "-fPIC", "-Wl,-Bsymbolic-functions", "-o"])
        .arg(&library)
        .arg(&path)
        .arg(&runtime)
        .args(ladder_engine::aot::toolchain::NATIVE_LIBS)
        .output()
        .map_err(|e| format!("cannot run `{compiler}`: {e}"))?;
    if !output.status.success() {
        return Err(format!(
            "`{compiler} -O2` failed on {}: {}",
            path.display(),
            String::from_utf8_lossy(&output.stderr)
        ));
    }
    Ok((library, built.layout))
}

fn set_inputs(mem: &mut Memory, scan: u32) {
    let pattern = scan.wrapping_mul(2_654_435_761);
    for (i, input) in mem.x.iter_mut().enumerate() {
        *input = ((pattern >> (i % 29)) & 1) as u8;
    }
    mem.elapsed_ms = 10;
}

fn c_backend(c: &mut Criterion) {
    let mut group = c.benchmark_group("c_backend");
    let programs = [
        ("bit_logic_11k", ladderc_benches::bit_logic(11_000, 1024, 1).il),
        ("plant_100_units", ladderc_benches::plant(100)),
    ];
    for (name, text) in programs {
        let (checked, diagnostics) = compile_source(&SourceFile::new(format!("{name}.il"), text.as_str()));
        let checked = checked.unwrap_or_else(|| panic!("{diagnostics:?}"));
        let jit = ladder_engine::pipeline::Lowered::new(&checked).jit().expect("compiles");
        let (library, compact) = match (
            c_library(name, &checked, &ImageRequest::full()),
            c_library(name, &checked, &ImageRequest::compact(Vec::new())),
        ) {
            (Ok((library, _)), Ok((compact, Some(layout)))) => (library, (compact, layout)),
            (Err(why), _) | (_, Err(why)) => {
                eprintln!("c_backend: skipped: {why}");
                return;
            }
            (Ok(_), Ok((_, None))) => panic!("a compact build has a compact layout"),
        };
        // SAFETY: the library was just built from the C back end's output;
        // `bench_body` has the declared signature.
        let library = unsafe { libloading::Library::new(&library) }.expect("loads the compiled C");
        let c_body: Body = *unsafe { library.get::<Body>(b"bench_body") }.expect("exports the body");

        // The same body scans leave the same whole image.
        let (mut jit_mem, mut c_mem) = (Memory::new_boxed(), Memory::new_boxed());
        for scan in 0..50 {
            set_inputs(&mut jit_mem, scan);
            set_inputs(&mut c_mem, scan);
            jit.run(&mut jit_mem);
            // SAFETY: a valid, exclusive image.
            unsafe { c_body(&mut *c_mem) };
        }
        assert!(
            bytemuck::bytes_of(&*jit_mem) == bytemuck::bytes_of(&*c_mem),
            "{name}: the C route left another image than Cranelift"
        );

        // The C route with a compact image: the same body on the program's
        // own layout, whose devices must end as the full image's did.
        let (compact_library, layout) = compact;
        // SAFETY: as above; `bench_init` has the declared signature.
        let compact_library = unsafe { libloading::Library::new(&compact_library) }.expect("loads the compiled C");
        let compact_body: CompactBody = *unsafe { compact_library.get::<CompactBody>(b"bench_body") }.expect("a body");
        let init: Init = *unsafe { compact_library.get::<Init>(b"bench_init") }.expect("an init");
        let mut storage = vec![0u32; layout.size as usize / 4];
        let size = storage.len() * 4;
        // SAFETY: writable, aligned storage of the image's size.
        let image = unsafe { init(storage.as_mut_ptr().cast(), size) };
        assert!(!image.is_null(), "{name}: the compact image was refused");
        // SAFETY: the image `init` just made, used only through this view
        // and the body below, one at a time.
        let compact_image = || unsafe { ImageMut::from_raw(image) }.expect("an initialised image");
        for scan in 0..50 {
            let pattern = (scan as u32).wrapping_mul(2_654_435_761);
            for x in 0..256 {
                compact_image().set_u8(Array::X, x, ((pattern >> (x % 29)) & 1) as u8);
            }
            compact_image().set_scalar(ladder_runtime::layout::Scalar::ElapsedMs, 10);
            // SAFETY: a valid, exclusive image of the body's layout.
            unsafe { compact_body(image) };
        }
        let full = bytemuck::bytes_of(&*jit_mem);
        let view = compact_image();
        for (run, segment) in layout.runs.iter().zip(SEGMENTS) {
            for n in run.first..run.first + run.count {
                let (array, size) = (segment.array, segment.array.size());
                let (at, held) = (ladder_runtime::layout::FULL.offset(array, n), view.offset(array, n));
                let (Some(at), Some(held)) = (at, held) else { continue };
                assert_eq!(
                    &full[at..at + size],
                    &view.bytes()[held..held + size],
                    "{name}: {array:?}[{n}] differs on the compact image"
                );
            }
        }

        let mut scan = 0u32;
        group.bench_function(BenchmarkId::new("cranelift", name), |b| {
            b.iter(|| {
                scan = scan.wrapping_add(1);
                jit_mem.x[0] = (scan & 1) as u8;
                jit.run(black_box(&mut jit_mem));
            })
        });
        group.bench_function(BenchmarkId::new("c_backend_gcc_O2", name), |b| {
            b.iter(|| {
                scan = scan.wrapping_add(1);
                c_mem.x[0] = (scan & 1) as u8;
                // SAFETY: as above.
                unsafe { c_body(black_box(&mut *c_mem)) };
            })
        });
        group.bench_function(BenchmarkId::new("c_backend_gcc_O2_compact_image", name), |b| {
            b.iter(|| {
                scan = scan.wrapping_add(1);
                compact_image().set_u8(Array::X, 0, (scan & 1) as u8);
                // SAFETY: as above.
                unsafe { compact_body(black_box(image)) };
            })
        });
    }
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().warm_up_time(std::time::Duration::from_secs(1)).measurement_time(std::time::Duration::from_secs(3));
    targets = c_backend
}
criterion_main!(benches);
