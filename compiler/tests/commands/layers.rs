//! The layers of docs/architecture.md ("Crates and layers"), held against
//! the dependency graph Cargo resolves: which ladder crates each crate may
//! use directly, and which heavy dependencies may never be anywhere below
//! it (Cranelift under the front end, an async runtime or a TLS stack under
//! anything but the server). Cargo enforces that a crate cannot reach up;
//! this test keeps the graph to the drawing.

use crate::common::tools::workspace;
use std::collections::{BTreeMap, BTreeSet};
use std::process::Command;

/// Each workspace crate, the ladder crates it may depend on, and the crates
/// (by name prefix) that must not be among its dependencies at any depth.
const LAYERS: &[(&str, &[&str], &[&str])] = &[
    (
        "ladder-runtime",
        &[],
        &["cranelift", "tokio", "axum", "rustls", "async-opcua", "hyper"],
    ),
    (
        "ladder-front",
        &["ladder-runtime"],
        &["cranelift", "tokio", "axum", "rustls", "async-opcua", "hyper"],
    ),
    (
        "ladder-interp",
        &["ladder-runtime", "ladder-front"],
        &["cranelift", "tokio", "axum", "rustls", "async-opcua", "hyper"],
    ),
    (
        "ladder-ir",
        &["ladder-runtime", "ladder-front"],
        &["cranelift", "tokio", "axum", "rustls", "async-opcua", "hyper"],
    ),
    (
        "ladder-codegen",
        &["ladder-runtime", "ladder-ir"],
        &["tokio", "axum", "rustls", "async-opcua", "hyper"],
    ),
    (
        "ladder-cback",
        &["ladder-runtime", "ladder-ir"],
        &["cranelift", "tokio", "axum", "rustls", "async-opcua", "hyper"],
    ),
    (
        "ladder-diagram",
        &["ladder-runtime", "ladder-front", "ladder-interp"],
        &["cranelift", "tokio", "axum", "rustls", "async-opcua", "hyper"],
    ),
    (
        "ladder-engine",
        &[
            "ladder-runtime",
            "ladder-front",
            "ladder-interp",
            "ladder-ir",
            "ladder-codegen",
            "ladder-cback",
        ],
        &["tokio", "axum", "rustls", "async-opcua", "hyper"],
    ),
    // Co-simulation: builds on the engine's pipeline and toolchain.
    (
        "ladder-fmu",
        &[
            "ladder-runtime",
            "ladder-front",
            "ladder-ir",
            "ladder-codegen",
            "ladder-engine",
        ],
        &["tokio", "axum", "rustls", "async-opcua", "hyper"],
    ),
    // Model checking: the interpreter is its transition relation, the
    // engine's pipeline its layout and its scenario runner the witnesses'
    // replay; no server.
    (
        "ladder-verify",
        &[
            "ladder-runtime",
            "ladder-front",
            "ladder-interp",
            "ladder-ir",
            "ladder-engine",
        ],
        &["tokio", "axum", "rustls", "async-opcua", "hyper"],
    ),
    // A plant protocol knows frames, not the PLC: no ladder crate at all.
    (
        "ladder-melsec",
        &[],
        &["cranelift", "tokio", "axum", "rustls", "async-opcua", "hyper"],
    ),
    // Modbus framing: no ladder crate; tokio only through tokio-modbus's
    // request and response types.
    (
        "ladder-modbus",
        &[],
        &["cranelift", "axum", "rustls", "async-opcua", "hyper"],
    ),
    (
        "ladder-serve",
        &[
            "ladder-melsec",
            "ladder-modbus",
            "ladder-runtime",
            "ladder-front",
            "ladder-interp",
            "ladder-ir",
            "ladder-codegen",
            "ladder-diagram",
            "ladder-engine",
        ],
        &[],
    ),
    (
        "ladderc",
        &[
            "ladder-runtime",
            "ladder-front",
            "ladder-interp",
            "ladder-ir",
            "ladder-codegen",
            "ladder-cback",
            "ladder-diagram",
            "ladder-engine",
            "ladder-fmu",
            "ladder-melsec",
            "ladder-modbus",
            "ladder-serve",
            "ladder-verify",
        ],
        &[],
    ),
];

/// Crates that only test, measure or fuzz: they may use any ladder crate but
/// ladderc's library, and nothing may depend on them.
const ABOVE_ALL: &[&str] = &["ladderc-testsuite", "ladderc-benches", "ladderc-fuzz"];

struct Graph {
    /// Package id → name.
    names: BTreeMap<String, String>,
    /// Package id → the ids of its normal (not dev, not build) dependencies.
    normal: BTreeMap<String, Vec<String>>,
    members: Vec<String>,
}

fn graph() -> Graph {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".to_string());
    let output = Command::new(cargo)
        .args(["metadata", "--format-version", "1", "--locked"])
        .current_dir(workspace())
        .output()
        .expect("cargo metadata runs");
    assert!(
        output.status.success(),
        "cargo metadata: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    let metadata: serde_json::Value = serde_json::from_slice(&output.stdout).expect("cargo metadata's JSON");
    let names = metadata["packages"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| {
            (
                p["id"].as_str().unwrap().to_string(),
                p["name"].as_str().unwrap().to_string(),
            )
        })
        .collect();
    let normal = metadata["resolve"]["nodes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|node| {
            let deps = node["deps"]
                .as_array()
                .unwrap()
                .iter()
                .filter(|dep| {
                    dep["dep_kinds"]
                        .as_array()
                        .unwrap()
                        .iter()
                        .any(|kind| kind["kind"].is_null())
                })
                .map(|dep| dep["pkg"].as_str().unwrap().to_string())
                .collect();
            (node["id"].as_str().unwrap().to_string(), deps)
        })
        .collect();
    let members = metadata["workspace_members"]
        .as_array()
        .unwrap()
        .iter()
        .map(|id| id.as_str().unwrap().to_string())
        .collect();
    Graph { names, normal, members }
}

impl Graph {
    fn id(&self, name: &str) -> &str {
        self.members
            .iter()
            .find(|id| self.names[*id] == name)
            .unwrap_or_else(|| panic!("{name} is a workspace member"))
    }

    fn direct(&self, id: &str) -> BTreeSet<&str> {
        self.normal[id].iter().map(|dep| self.names[dep].as_str()).collect()
    }

    fn closure(&self, id: &str) -> BTreeSet<&str> {
        let mut seen = BTreeSet::new();
        let mut pending = vec![id];
        while let Some(next) = pending.pop() {
            for dep in &self.normal[next] {
                if seen.insert(self.names[dep].as_str()) {
                    pending.push(dep);
                }
            }
        }
        seen
    }
}

#[test]
fn every_crate_keeps_to_its_layer() {
    let graph = graph();
    let mut problems = Vec::new();
    let is_ladder = |name: &str| name.starts_with("ladder");
    for (name, allowed, never) in LAYERS {
        let id = graph.id(name);
        for dep in graph.direct(id).into_iter().filter(|dep| is_ladder(dep)) {
            if !allowed.contains(&dep) {
                problems.push(format!("{name} depends on {dep}, which its layer does not allow"));
            }
        }
        for dep in graph.closure(id) {
            if let Some(prefix) = never.iter().find(|prefix| dep.starts_with(**prefix)) {
                problems.push(format!("{name} pulls in {dep} ({prefix} must stay out of its layer)"));
            }
        }
    }
    for id in &graph.members {
        let name = graph.names[id].as_str();
        if !LAYERS.iter().any(|(layer, _, _)| *layer == name) && !ABOVE_ALL.contains(&name) {
            problems.push(format!("{name} is a workspace member without a layer in this test"));
        }
        for dep in graph.direct(id) {
            if ABOVE_ALL.contains(&dep) {
                problems.push(format!("{name} depends on {dep}, which nothing may depend on"));
            }
            if dep == "ladderc" {
                problems.push(format!(
                    "{name} depends on ladderc's library (the commands), not on a layer"
                ));
            }
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn the_front_end_and_the_interpreter_build_without_code_generators_or_servers() {
    let graph = graph();
    for name in ["ladder-front", "ladder-interp"] {
        let closure = graph.closure(graph.id(name));
        for heavy in ["cranelift-codegen", "tokio", "axum", "rustls", "async-opcua"] {
            assert!(!closure.contains(heavy), "{name} depends on {heavy}: {closure:?}");
        }
        assert!(
            closure.len() < 40,
            "{name} has {} dependencies: {closure:?}",
            closure.len()
        );
    }
}
