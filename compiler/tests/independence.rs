//! The reference interpreter is the specification the native engines are
//! tested against, so it must not share their code: it never uses the IR,
//! the lowering, the code generator, or the runtime's helpers and block
//! operations for compiled code. (Shared on purpose: the device image, the
//! scan steps, timers, counters and `Place` access — see
//! docs/architecture.md.) Nor does the C back end share Cranelift's translation.

use std::path::Path;

const FORBIDDEN: &[&str] = &[
    "crate::ir",
    "crate::lower",
    "crate::codegen",
    "crate::cback",
    "crate::pipeline",
    "crate::aot",
    "ladder_runtime::helpers",
    "ladder_runtime::compiled",
    "helpers::",
    "compiled::",
    "ladder_rt_",
];

fn sources(dir: &Path, out: &mut Vec<(String, String)>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            sources(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push((path.display().to_string(), std::fs::read_to_string(&path).unwrap()));
        }
    }
}

#[test]
fn the_interpreter_uses_none_of_the_compiled_path() {
    let mut files = Vec::new();
    sources(&Path::new(env!("CARGO_MANIFEST_DIR")).join("src/interp"), &mut files);
    assert!(files.len() >= 5, "found the interpreter's sources");
    let mut found = Vec::new();
    for (path, text) in &files {
        for (number, line) in text.lines().enumerate() {
            let code = line.split("//").next().unwrap_or("");
            for forbidden in FORBIDDEN {
                if code.contains(forbidden) {
                    found.push(format!("{path}:{}: uses `{forbidden}`", number + 1));
                }
            }
        }
    }
    assert!(found.is_empty(), "{}", found.join("\n"));
}

/// The C back end is checked against the interpreter as an engine of its
/// own, so it must not share Cranelift's translation: it reads the IR and
/// the layout, nothing of `codegen`.
#[test]
fn the_c_back_end_shares_nothing_with_cranelift_s_translation() {
    let mut files = Vec::new();
    sources(&Path::new(env!("CARGO_MANIFEST_DIR")).join("src/cback"), &mut files);
    assert!(files.len() >= 3, "found the C back end's sources");
    let found: Vec<String> = files
        .iter()
        .flat_map(|(path, text)| {
            text.lines().enumerate().filter_map(move |(number, line)| {
                let code = line.split("//").next().unwrap_or("");
                ["crate::codegen", "cranelift"]
                    .iter()
                    .find(|forbidden| code.contains(*forbidden))
                    .map(|forbidden| format!("{path}:{}: uses `{forbidden}`", number + 1))
            })
        })
        .collect();
    assert!(found.is_empty(), "{}", found.join("\n"));
}
