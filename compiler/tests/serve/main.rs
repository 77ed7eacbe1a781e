//! `ladderc serve` end to end: the real binary on loopback, with real
//! clients (Modbus TCP, HTTP, server-sent events, OPC UA, a headless
//! browser). One test binary, one module per concern.

#[path = "../common/mod.rs"]
mod common;

mod serve;
mod serve_bounds;
mod serve_opcua;
mod serve_protocols;
mod serve_soak;
mod serve_unattended;
mod serve_web;
