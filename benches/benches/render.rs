//! Drawing a program: ladder model, layout and SVG of `ladderc render`,
//! for plant programs of about 1,400 and 10,000 rungs (the mark:
//! 10,000 rungs in under 2 s). Compiling is outside the measurement.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use ladder_front::check::compile_source;
use ladder_front::source::SourceFile;
use std::hint::black_box;

fn render(c: &mut Criterion) {
    let mut group = c.benchmark_group("render");
    group.sample_size(10);
    for units in [100u32, 720] {
        let source = SourceFile::new("plant.il", ladderc_benches::plant(units));
        let (program, diagnostics) = compile_source(&source);
        let program = program.unwrap_or_else(|| panic!("{:?}", diagnostics.first()));
        let rungs = ladder_diagram::build(&program, &source).rungs.len();
        eprintln!("render: {units} units = {rungs} rungs");
        group.throughput(Throughput::Elements(rungs as u64));
        group.bench_with_input(BenchmarkId::new("rungs", rungs), &program, |b, program| {
            b.iter(|| {
                let ladder = ladder_diagram::build(program, &source);
                black_box(ladder_diagram::svg::render(&ladder, program).len())
            })
        });
    }
    group.finish();
}

criterion_group!(benches, render);
criterion_main!(benches);
