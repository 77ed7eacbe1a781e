//! The commands, engines and hosts end to end: the `ladderc` binary, the
//! object file and generated C linked into C hosts, the ladder diagram,
//! the instruction table. One test binary, one module per concern.

#[path = "../common/mod.rs"]
mod common;

/// Many of these tests wait on other processes (the C compiler, Python
/// clients, QEMU): four at a time on a two-core machine take 36 s where two
/// take 47 s. Set before the test harness reads it, and only when the
/// caller chose nothing (`--test-threads` and `RUST_TEST_THREADS` still
/// decide).
#[ctor::ctor(unsafe)]
fn process_bound_tests_run_four_at_a_time() {
    if std::env::var_os("RUST_TEST_THREADS").is_none() {
        std::env::set_var("RUST_TEST_THREADS", "4");
    }
}

mod c_header;
mod c_route;
mod cli;
mod cli_rough_edges;
mod code_map;
mod code_size;
mod compact_image;
mod cross_targets;
mod emulated_controllers;
mod fmu_export;
mod frontend_never_panics;
mod gx_developer;
mod helper_docs;
mod independence;
mod instruction_table;
mod ladder;
mod layers;
mod native_hosts;
mod program_files;
mod tidy;
mod verify;
mod watch_and_report;
