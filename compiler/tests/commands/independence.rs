//! The reference interpreter is the specification the native engines are
//! tested against, so it must not share their code. Which crates it may use
//! is Cargo's business (`layers.rs`: not the IR, the lowering or either code
//! generator); this test keeps the one rule Cargo cannot see: inside the
//! runtime, which it shares on purpose (the device image, the scan steps,
//! timers, counters, `Place` access — see docs/architecture.md), it never
//! uses the helpers and block operations written for compiled code.

use crate::common::tools::workspace;
use std::path::Path;

const FORBIDDEN: &[&str] = &[
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
fn the_interpreter_uses_none_of_the_runtime_s_compiled_code_helpers() {
    let mut files = Vec::new();
    sources(&workspace().join("crates/interp/src"), &mut files);
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
