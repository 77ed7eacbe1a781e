//! Every Rust file of the workspace says what it is for: it opens with a
//! `//!` header. The files are every `.rs` under a workspace member's folder
//! (sources, tests, benches, fuzz targets; build output and hidden folders
//! left out). Before the header only blank lines, plain `//` comments (a
//! licence line, say) and inner attributes (`#![no_main]`) may stand.

use super::code_map::{files_under, workspace_members};
use crate::common::tools::workspace;

/// Whether `text` opens with a `//!` header, after what may stand before it.
fn opens_with_a_header(text: &str) -> bool {
    let first = text.lines().map(str::trim).find(|line| {
        let comment = line.starts_with("//") && !line.starts_with("///") && !line.starts_with("//!");
        !(line.is_empty() || comment || line.starts_with("#!["))
    });
    first.is_some_and(|line| line.starts_with("//!"))
}

#[test]
fn the_header_rule_reads_files_as_meant() {
    assert!(opens_with_a_header("//! A module.\nfn f() {}\n"));
    assert!(opens_with_a_header("\n// SPDX: MIT\n#![no_main]\n//! A target.\n"));
    assert!(!opens_with_a_header("/// An item's doc.\nfn f() {}\n"));
    assert!(!opens_with_a_header("use std::fmt;\n//! Too late.\n"));
    assert!(!opens_with_a_header(""));
}

#[test]
fn every_rust_file_opens_with_a_header() {
    let root = workspace();
    let mut files = Vec::new();
    for member in workspace_members(&root) {
        files_under(&root.join(member), &["rs"], &mut files);
    }
    assert!(files.len() > 200, "found the Rust files: {}", files.len());
    let mut offenders: Vec<String> = files
        .iter()
        .filter(|file| !opens_with_a_header(&std::fs::read_to_string(file).unwrap()))
        .map(|file| file.strip_prefix(&root).unwrap().display().to_string())
        .collect();
    offenders.sort();
    assert!(
        offenders.is_empty(),
        "these files do not open with a `//!` header saying what they are for:\n{}",
        offenders.join("\n")
    );
}
