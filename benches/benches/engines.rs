//! Scan time of the reference interpreter against the JIT on the same
//! programs, and the cost of compiling. Read ratios within one run: absolute
//! times drift on shared machines.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use ladder_front::check::compile_source;
use ladder_front::program::CheckedProgram;
use ladder_front::source::SourceFile;
use ladder_interp::Interpreter;
use ladder_runtime::Memory;
use std::hint::black_box;
use std::path::Path;

fn checked(name: &str, text: &str) -> CheckedProgram {
    let (program, diagnostics) = compile_source(&SourceFile::new(name, text));
    program.unwrap_or_else(|| panic!("{name}: {diagnostics:?}"))
}

fn workspace_file(relative: &str) -> String {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).parent().expect("workspace");
    std::fs::read_to_string(root.join(relative)).expect("program file")
}

fn programs() -> Vec<(String, CheckedProgram)> {
    vec![
        (
            "traffic_light".into(),
            checked("traffic", &workspace_file("examples/traffic_light.il")),
        ),
        (
            "motor".into(),
            checked("motor", &workspace_file("examples/motor_start_stop.il")),
        ),
        (
            "offsets".into(),
            checked("offsets", &workspace_file("testsuite/programs/offsets_out_of_range.il")),
        ),
        ("plant_400_units".into(), checked("plant", &ladderc_benches::plant(400))),
        (
            "fx_station".into(),
            checked("fx_station", &workspace_file("testsuite/programs/fx/fx_station.il")),
        ),
        // 1,000 FOR/NEXT repetitions over an index-register table, and a
        // subroutine called every scan.
        (
            "loop_1000_and_call".into(),
            checked(
                "loop",
                "LD SM0\nMOV K0 Z0\nFOR K1000\nLD SM0\nADD D100Z0 D0 D100Z0\nINC Z0\nNEXT\nLD SM0\nCALL P0\nFEND\nP0\nLD X0\nINC D0\nSRET\n",
            ),
        ),
    ]
}

/// Inputs X0..X37 change every scan, so edges and seal-ins do real work.
fn stimulate(mem: &mut Memory, scan: u32) {
    let pattern = scan.wrapping_mul(2654435761) >> 4;
    for (i, input) in mem.input_image.iter_mut().take(32).enumerate() {
        *input = ((pattern >> i) & 1) as u8;
    }
}

fn scan_time(c: &mut Criterion) {
    let mut group = c.benchmark_group("scan");
    for (name, program) in programs() {
        let interpreter = Interpreter::new(&program);
        let jit = ladder_engine::pipeline::Lowered::new(&program).jit().expect("compiles");
        let mut mem = Memory::new_boxed();
        let mut scan = 0u32;
        group.bench_function(BenchmarkId::new("interp", &name), |b| {
            b.iter(|| {
                scan = scan.wrapping_add(1);
                stimulate(&mut mem, scan);
                interpreter.scan(black_box(&mut mem), 10);
            })
        });
        let mut mem = Memory::new_boxed();
        group.bench_function(BenchmarkId::new("jit", &name), |b| {
            b.iter(|| {
                scan = scan.wrapping_add(1);
                stimulate(&mut mem, scan);
                mem.scan_with(10, |m| jit.run(black_box(m)));
            })
        });
    }
    group.finish();
}

/// The instructions compiled code hands to runtime helpers, each in a
/// program of its own: SORT2P of a 32 × 6 table (M0 toggles every scan, so
/// the P form sorts the whole table every other scan), CRC of 256 bytes and
/// MEAN of 512 words every scan. D0 changes every scan.
fn helper_instructions(c: &mut Criterion) {
    let programs = [
        (
            "sort2_32x6",
            "LDI M0\nOUT M0\nLD SM0\nINC D0\nLD M0\nSORT2P D0 K32 K6 D300 K2\n",
        ),
        ("crc_256_bytes", "LD SM0\nINC D0\nCRC D0 D1000 K256\n"),
        ("mean_512_words", "LD SM0\nINC D0\nMEAN D0 D1000 K512\n"),
    ];
    let mut group = c.benchmark_group("helpers");
    for (name, text) in programs {
        let program = checked(name, text);
        let interpreter = Interpreter::new(&program);
        let jit = ladder_engine::pipeline::Lowered::new(&program).jit().expect("compiles");
        let mut mem = Memory::new_boxed();
        for (i, word) in mem.d.iter_mut().take(600).enumerate() {
            *word = (i as i16).wrapping_mul(7919);
        }
        let mut jit_mem = mem.clone();
        group.bench_function(BenchmarkId::new("interp", name), |b| {
            b.iter(|| interpreter.scan(black_box(&mut mem), 10))
        });
        group.bench_function(BenchmarkId::new("jit", name), |b| {
            b.iter(|| jit_mem.scan_with(10, |m| jit.run(black_box(m))))
        });
    }
    group.finish();
}

fn compile_time(c: &mut Criterion) {
    let text = ladderc_benches::plant(100);
    let program = checked("plant", &text);
    let mut group = c.benchmark_group("compile_plant_100_units");
    group.sample_size(10);
    group.bench_function("check", |b| b.iter(|| checked("plant", black_box(&text))));
    group.bench_function("lower_and_optimise", |b| {
        b.iter(|| ladder_engine::pipeline::Lowered::new(black_box(&program)))
    });
    group.bench_function("jit", |b| {
        b.iter(|| {
            ladder_engine::pipeline::Lowered::new(black_box(&program))
                .jit()
                .expect("compiles")
        })
    });
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().warm_up_time(std::time::Duration::from_secs(1)).measurement_time(std::time::Duration::from_secs(3));
    targets = scan_time, helper_instructions, compile_time
}
criterion_main!(benches);
