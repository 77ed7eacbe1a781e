//! Fuzz targets of ladderc, shared by the cargo-fuzz (libFuzzer, nightly)
//! and AFL++ (stable) binaries. Each must never panic, whatever the bytes:
//!
//! - `front_end`: a program file → diagnostics rendered (file:line:col);
//! - `scenario`: a scenario file → parsed, and when its program is inline,
//!   run on the interpreter and the JIT (a bounded number of scans);
//! - `pipeline`: a program file → check → IR → native code (JIT and an
//!   object file) → a few scans of interpreter and JIT with varied inputs
//!   and registers, whose whole images must be equal (a differential check
//!   on whatever the fuzzer finds);
//! - `modbus`: a client's bytes on a `serve` Modbus TCP connection → framed
//!   and answered as the server does; every answer well formed;
//! - `melsec`: a client's bytes on a `serve` MELSEC connection (1E, 3E,
//!   4E; binary and ASCII) → framed and answered as the server does; every
//!   answer of its frame's kind, route and length;
//! - `modbus_rtu`: frames on a `serve` Modbus RTU line → answered as the
//!   slave answers them: only its unit, from it, with a matching CRC;
//! - `http`: a request (method, path and query, body) to `serve`'s HTTP
//!   router with its access layer → never a 5xx;
//! - `gx_developer`: a GX Developer file (the first byte picks MAIN.wpg,
//!   COMMENT.wcd or param.wpa) → decoded or one error at an offset inside
//!   the file; a program that decodes is compiled, written back and
//!   decoded again to the same instructions.

use ladder_engine::scenario::{parse_scenario, run_scenario, Directive, EngineKind, ProgramSource};
use ladder_front::check::compile_source;
use ladder_front::diagnostics::render_all;
use ladder_front::source::SourceFile;
use ladder_interp::Interpreter;
use ladder_runtime::Memory;

/// The scans a fuzzed scenario may run (keeps each execution short).
const SCENARIO_SCAN_BUDGET: u64 = 500;

pub fn front_end(data: &[u8]) {
    let file = SourceFile::from_bytes("fuzz.il", data);
    let (_, diagnostics) = compile_source(&file);
    let _ = render_all(&file, &diagnostics, ladder_front::diagnostics::Shown::All);
}

/// A GX Developer file: the first byte picks the reader (program,
/// comments, parameters). Never a panic; an error names an offset inside
/// the file; a program that decodes and compiles writes back to a file
/// that decodes to the same instructions.
pub fn gx_developer(data: &[u8]) {
    use ladder_front::gxdev::{listing_of, wcd, wpa, write};
    let Some((&which, bytes)) = data.split_first() else {
        return;
    };
    match which % 3 {
        0 => {
            let listing = match listing_of(("MAIN.wpg", bytes), None, None) {
                Ok(listing) => listing,
                Err(error) => {
                    assert!(error.error.offset <= bytes.len(), "{error}");
                    return;
                }
            };
            let file = SourceFile::new("MAIN.wpg", listing.clone());
            let (Some(_), _) = compile_source(&file) else {
                return;
            };
            // Written into the largest program memory (a file may count
            // steps otherwise than the FX manuals do): without the
            // listing's own `//@ memory` line, which would have to match.
            let defaults = write::Defaults {
                cpu: None,
                memory: Some(64_000),
            };
            let unsized_listing: String = listing
                .lines()
                .filter(|l| !l.starts_with("//@ memory"))
                .map(|l| format!("{l}\n"))
                .collect();
            let file = SourceFile::new("MAIN.wpg", unsized_listing);
            if let Ok((program, _)) = write::encode(&file, &defaults) {
                let again = listing_of(("MAIN.wpg", &program), None, None).expect("a written program decodes");
                // The instructions and labels, without their steps (a file
                // may count them otherwise than the FX manuals do) and
                // comments.
                let body = |text: &str| {
                    text.lines()
                        .filter(|l| !l.trim_start().starts_with("//") && !l.trim_start().starts_with(';'))
                        .map(|l| {
                            let l = l.split(" ; ").next().unwrap_or_default();
                            l.trim_start_matches(|c: char| c.is_ascii_digit()).trim().to_string()
                        })
                        .collect::<Vec<_>>()
                };
                assert_eq!(body(&again), body(&listing), "a written program reads back as another");
            }
        }
        1 => {
            if let Err(error) = wcd::decode(bytes) {
                assert!(error.offset <= bytes.len(), "{error:?}");
            }
        }
        _ => {
            if let Err(error) = wpa::decode(bytes) {
                assert!(error.offset <= bytes.len(), "{error:?}");
            }
        }
    }
}

/// A property file (`ladderc verify`): diagnosed or checked, never a
/// panic; inline programs are searched within tight limits, by the
/// default engines or (an odd length) the SAT-based ones alone.
pub fn properties(data: &[u8]) {
    let file = SourceFile::from_bytes("fuzz.prop", data);
    let engine = if data.len() % 2 == 1 {
        ladder_verify::Engine::Symbolic
    } else {
        ladder_verify::Engine::Auto
    };
    let options = ladder_verify::Options {
        engine,
        limits: ladder_verify::search::Limits {
            depth: 50,
            timeout: std::time::Duration::from_millis(200),
            states: 20_000,
            branching: 256,
            memory: 64 << 20,
        },
    };
    let _ = ladder_verify::verify_source(std::path::Path::new("fuzz.prop"), &file, &options);
}

pub fn scenario(data: &[u8]) {
    let text = String::from_utf8_lossy(data);
    let Ok(scenario) = parse_scenario(std::path::Path::new("fuzz.scn"), &text) else {
        return;
    };
    let ProgramSource::Inline { text, .. } = &scenario.program else {
        // Never read files named by fuzzed input.
        return;
    };
    let scans: u64 = scenario
        .steps
        .iter()
        .map(|step| match step.directive {
            Directive::Scan(n) => u64::from(n),
            Directive::ScanMs(_)
            | Directive::Set { .. }
            | Directive::Force { .. }
            | Directive::Unforce { .. }
            | Directive::Expect { .. }
            | Directive::ExpectError(_)
            | Directive::ExpectReject { .. }
            | Directive::ExpectReal { .. }
            | Directive::Pulse { .. }
            | Directive::Clock(_)
            | Directive::Print(_) => 0,
        })
        .sum();
    if scans > SCENARIO_SCAN_BUDGET {
        return;
    }
    let source = SourceFile::new("fuzz.scn (program)", text.as_str());
    let _ = run_scenario(
        &scenario,
        &source,
        &[EngineKind::Interp, EngineKind::Jit],
        Default::default(),
    );
}

pub fn pipeline(data: &[u8]) {
    let file = SourceFile::from_bytes("fuzz.il", data);
    let (program, diagnostics) = compile_source(&file);
    let _ = render_all(&file, &diagnostics, ladder_front::diagnostics::Shown::All);
    let Some(program) = program else {
        return;
    };
    let options = ladder_codegen::ObjectOptions {
        target: None,
        prefix: ladder_codegen::DEFAULT_PREFIX.to_string(),
        layout: None,
        ..Default::default()
    };
    // Both images: the full one, and a compact one laid out from the program.
    let lowered = ladder_engine::pipeline::Lowered::new(&program);
    for image in [
        ladder_engine::pipeline::ImageRequest::full(),
        ladder_engine::pipeline::ImageRequest::compact(Vec::new()),
    ] {
        lowered
            .object(&options, &image)
            .expect("a checked program compiles to an object");
    }
    let jit = lowered.jit().expect("a checked program compiles to native code");
    let interpreter = Interpreter::new(&program);
    let mut expected = Memory::new_boxed();
    let mut actual = Memory::new_boxed();
    let registers = [-1i16, 3, 8511, -32768, 32767, 200, 7, 0];
    for scan in 0..4u32 {
        for mem in [&mut expected, &mut actual] {
            for (i, value) in registers.iter().enumerate() {
                mem.d[i] = value.wrapping_add(scan as i16);
            }
            for (x, input) in mem.input_image.iter_mut().enumerate().take(16) {
                *input = u8::from((x as u32 + scan).is_multiple_of(3));
            }
        }
        let elapsed = [10, 0, u32::MAX, 100][scan as usize];
        interpreter.scan(&mut expected, elapsed);
        actual.scan_with(elapsed, |mem| jit.run(mem));
        assert!(
            bytemuck::bytes_of(&*expected) == bytemuck::bytes_of(&*actual),
            "the JIT's image differs from the interpreter's after scan {}",
            scan + 1
        );
    }
}

pub fn modbus(data: &[u8]) {
    ladder_serve::fuzzing::modbus_stream(data);
}

pub fn melsec(data: &[u8]) {
    ladder_serve::fuzzing::melsec_stream(data);
}

pub fn modbus_rtu(data: &[u8]) {
    ladder_serve::fuzzing::modbus_rtu_frames(data);
}

pub fn http(data: &[u8]) {
    ladder_serve::fuzzing::http_request(data);
}
