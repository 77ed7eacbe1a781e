//! Build cost against program size: compile time per instruction (criterion,
//! throughput in instructions) and peak heap per instruction (a counting
//! allocator), from 1k to 1M instructions. Both should stay flat: the
//! compiler is linear. Peak heap is printed before the timings, e.g.
//!
//! ```text
//! compile memory: 1000 instructions: peak heap 1.2 KB per instruction
//! ```

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use ladder_codegen::ObjectOptions;
use ladder_front::check::compile_source;
use ladder_front::source::SourceFile;
use std::hint::black_box;

#[global_allocator]
static ALLOCATOR: ladderc_benches::heap::Counting = ladderc_benches::heap::Counting;

/// Check, lower, optimise and emit an object file: `ladderc build`.
fn build(text: &str) -> usize {
    let (program, diagnostics) = compile_source(&SourceFile::new("bench.il", text));
    let program = program.unwrap_or_else(|| panic!("{:?}", diagnostics.first()));
    ladder_engine::pipeline::Lowered::new(&program)
        .object(
            &ObjectOptions::default(),
            &ladder_engine::pipeline::ImageRequest::full(),
        )
        .expect("compiles")
        .output
        .len()
}

fn peak_heap_per_instruction() {
    for instructions in [1_000, 10_000, 100_000, 1_000_000] {
        let program = ladderc_benches::bit_logic(instructions, 1024, 7);
        let before = ladderc_benches::heap::start();
        black_box(build(&program.il));
        let peak = ladderc_benches::heap::peak_since(before);
        eprintln!(
            "compile memory: {} instructions: peak heap {:.2} KB per instruction",
            program.instructions,
            peak as f64 / program.instructions as f64 / 1024.0
        );
    }
    let adds: String = (0..60_000)
        .map(|i| format!("LD X{}\nADD D{} K3 D{}\n", i % 8, i % 4000, (i + 1) % 4000))
        .collect();
    let before = ladderc_benches::heap::start();
    black_box(build(&adds));
    eprintln!(
        "compile memory: 60000 ADD rungs: peak heap {:.2} KB per instruction",
        ladderc_benches::heap::peak_since(before) as f64 / 120_000.0 / 1024.0
    );
}

fn compile_time(c: &mut Criterion) {
    peak_heap_per_instruction();
    let mut group = c.benchmark_group("build");
    group.sample_size(10);
    for instructions in [1_000, 10_000, 100_000] {
        let program = ladderc_benches::bit_logic(instructions, 1024, 7);
        group.throughput(Throughput::Elements(program.instructions as u64));
        group.bench_function(BenchmarkId::new("bit_logic", program.instructions), |b| {
            b.iter(|| build(black_box(&program.il)))
        });
    }
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().warm_up_time(std::time::Duration::from_secs(1)).measurement_time(std::time::Duration::from_secs(5));
    targets = compile_time
}
criterion_main!(benches);
