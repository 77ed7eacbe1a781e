//! The commands, engines and hosts end to end: the `ladderc` binary, the
//! object file and generated C linked into C hosts, the ladder diagram,
//! the instruction table. One test binary, one module per concern.

#[path = "../common/mod.rs"]
mod common;

mod c_header;
mod c_route;
mod cli;
mod cli_rough_edges;
mod code_map;
mod compact_image;
mod cross_targets;
mod emulated_controllers;
mod fmu_export;
mod frontend_never_panics;
mod helper_docs;
mod independence;
mod instruction_table;
mod ladder;
mod layers;
mod native_hosts;
mod program_files;
mod watch_and_report;
