//! `ladderc serve` end to end: the real binary on loopback, with real
//! clients (Modbus TCP, HTTP, server-sent events, OPC UA, a headless
//! browser). One test binary, one module per concern.

#[path = "../common/mod.rs"]
mod common;

/// These tests mostly wait: on sockets, on the server's timeouts, on a
/// headless browser. Six at a time on a two-core machine take the binary
/// from 91 s of waiting, one after another, to 26-27 s here (four: 33 s;
/// eight: 23-25 s, with less headroom for the tests that time scans), where
/// the compiling and simulating test binaries gain nothing from more
/// threads than cores. Set before the test harness reads it, and only when
/// the caller chose nothing (`--test-threads` and `RUST_TEST_THREADS` still
/// decide).
#[ctor::ctor(unsafe)]
fn wait_bound_tests_run_six_at_a_time() {
    if std::env::var_os("RUST_TEST_THREADS").is_none() {
        std::env::set_var("RUST_TEST_THREADS", "6");
    }
}

mod serve;
mod serve_bounds;
mod serve_gx_developer;
mod serve_melsec;
mod serve_melsec_clients;
mod serve_modbus_rtu;
mod serve_opcua;
mod serve_protocols;
mod serve_read_after_write;
mod serve_remote_io;
mod serve_soak;
mod serve_unattended;
mod serve_web;
