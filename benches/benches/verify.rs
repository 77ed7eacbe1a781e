//! `ladderc verify`: time and peak heap per verdict, for the property suite
//! (`testsuite/properties/`) and for a plant of 60 reversing starters (1,140
//! instructions) with a dozen interlock, stop and reach properties. Printed
//! before criterion's timings, e.g.
//!
//! ```text
//! verify plant.prop:3: proved (13 states, 112 scans searched)
//! verify plant.prop: 14 properties in 409.9 ms, peak heap 3.1 MB
//! ```
//!
//! The plant and the suite again with the SAT-based engines alone
//! (`[sat]`), and a program whose properties read 17 free input bits (a
//! 16-bit code on K4X0 and an enable), past the explicit search's 12, which
//! the default engines hand to the SAT-based ones.
//!
//! Marks (issue "Prove it before it runs"): every property of the suite
//! decided, an interlock of a 1,000-instruction program proved in under
//! 10 s, peak memory under 1 GB.

use criterion::{criterion_group, criterion_main, Criterion};
use ladder_verify::{collect_files, verify_file, Engine, Options};
use std::fmt::Write as _;
use std::hint::black_box;
use std::path::{Path, PathBuf};
use std::time::Instant;

#[global_allocator]
static ALLOCATOR: ladderc_benches::heap::Counting = ladderc_benches::heap::Counting;

/// Units of the plant.
const UNITS: u32 = 60;

/// A plant of reversing starters: each unit's forward and reverse inputs,
/// a shared stop, the interlock, a run timer, a start counter and a run
/// time register (19 instructions a unit).
fn plant() -> String {
    let mut text = String::new();
    for u in 0..UNITS {
        let (forward, reverse) = (2 * u + 1, 2 * u + 2);
        let x = |n: u32| format!("X{n:o}");
        let (fy, ry) = (2 * u, 2 * u + 1);
        let _ = write!(
            text,
            "LD {f}\nOR Y{fy:o}\nANI X0\nANI Y{ry:o}\nOUT Y{fy:o}\n\
             LD {r}\nOR Y{ry:o}\nANI X0\nANI Y{fy:o}\nOUT Y{ry:o}\n\
             LD Y{fy:o}\nOR Y{ry:o}\nOUT T{u} K50\n\
             LD T{u}\nOUT C{u} K1000\nLD C{u}\nRST C{u}\nLD T{u}\nINC D{u}\n",
            f = x(forward),
            r = x(reverse),
        );
    }
    text
}

/// A dozen properties of the plant: interlocks, the stop, reach.
fn plant_properties(program: &Path) -> String {
    let mut text = format!("program {}\nscan-ms 10\n", program.display());
    for u in [0, 7, 19, 33, 47, 59] {
        let (fy, ry) = (2 * u, 2 * u + 1);
        let _ = writeln!(text, "never Y{fy:o} & Y{ry:o}");
        let _ = writeln!(text, "respond X0 -> !Y{fy:o} & !Y{ry:o} within 0");
    }
    let _ = writeln!(text, "reach Y{:o}", 2 * 59 + 1);
    let _ = writeln!(text, "never T0 & !Y0 & !Y1");
    text
}

/// A code lock: Y0 when the 16 inputs X0-X17 show 12345, Y1 when X20 is
/// ON too; 17 free input bits reach Y1.
const CODE_LOCK: &str = "program <<\nLD= K4X0 K12345\nOUT Y0\nLD Y0\nAND X20\nOUT Y1\n>>\n\
                         never Y1 & !Y0\nreach Y1\nnever Y1 & !X20\n";

/// Verifies `file` once, printing each verdict with its time and states,
/// and the file's peak heap.
fn report(file: &Path, options: &Options) {
    let heap = ladderc_benches::heap::start();
    let start = Instant::now();
    let reports = verify_file(file, options).expect("a property file that checks");
    let took = start.elapsed();
    let peak = ladderc_benches::heap::peak_since(heap);
    let mut name = file
        .file_name()
        .map_or(String::new(), |n| n.to_string_lossy().into_owned());
    if options.engine == Engine::Symbolic {
        name.push_str(" [sat]");
    }
    for report in &reports {
        let how = match &report.searched.by_sat {
            Some(by) => by.clone(),
            None => format!(
                "{} states, {} scans searched",
                report.searched.states, report.searched.transitions
            ),
        };
        println!("verify {name}:{}: {} ({how})", report.line, report.verdict.text());
    }
    println!(
        "verify {name}: {} properties in {:.1} ms, peak heap {:.1} MB",
        reports.len(),
        took.as_secs_f64() * 1e3,
        peak as f64 / 1e6
    );
}

fn suite() -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../testsuite/properties");
    collect_files(&dir).expect("the property suite")
}

fn bench(c: &mut Criterion) {
    let work = tempfile::tempdir().expect("a scratch folder");
    let program = work.path().join("plant.il");
    std::fs::write(&program, plant()).expect("the plant");
    let properties = work.path().join("plant.prop");
    std::fs::write(&properties, plant_properties(&program)).expect("its properties");
    let lock = work.path().join("code_lock.prop");
    std::fs::write(&lock, CODE_LOCK).expect("the code lock");
    let files: Vec<PathBuf> = suite().into_iter().chain([properties.clone(), lock.clone()]).collect();
    for file in &files {
        report(file, &Options::default());
    }
    // Ten seconds a property: what the SAT engines do not decide by
    // then (the traffic light's timers) the explicit search does in ms.
    let sat = Options {
        engine: Engine::Symbolic,
        limits: ladder_verify::search::Limits {
            timeout: std::time::Duration::from_secs(10),
            ..Default::default()
        },
    };
    for file in &files {
        report(file, &sat);
    }
    c.bench_function("verify/suite", |b| {
        b.iter(|| {
            for file in suite() {
                black_box(verify_file(&file, &Options::default()).expect("checks"));
            }
        })
    });
    c.bench_function("verify/plant_1140_instructions", |b| {
        b.iter(|| black_box(verify_file(&properties, &Options::default()).expect("checks")))
    });
    c.bench_function("verify/plant_1140_instructions_sat", |b| {
        b.iter(|| black_box(verify_file(&properties, &sat).expect("checks")))
    });
    c.bench_function("verify/code_lock_17_inputs", |b| {
        b.iter(|| black_box(verify_file(&lock, &Options::default()).expect("checks")))
    });
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(10);
    targets = bench
}
criterion_main!(benches);
