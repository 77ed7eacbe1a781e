//! `ladderc serve --melsec` against MELSEC clients from PyPI, each run as
//! its users run it (`melsec_clients.py`): pymcprotocol (3E and 4E, binary
//! and ASCII, Q and iQ-R device forms), slmp-connect-python (its iQ-F
//! profile in 3E over TCP and UDP, 4E with the iQ-F numbering, its iQ-R
//! profile) and fx3u-mcprotocol (1E ASCII, as an FX3U-ENET-ADP answers).
//! Where a package cannot be installed the test says why it skipped.

use crate::common::server::{modbus_connect, modbus_request, Server};
use crate::common::tools::{ensure_python_module, skip};

const CLIENTS: &str = include_str!("melsec_clients.py");

/// A seal-in (X0 sets Y0, X1 resets it), D101 follows D100, Y7 follows M5,
/// D0 counts scans.
const PROGRAM: &str = "LD X0\nOR Y0\nANI X1\nOUT Y0\nLD M8000\nMOV D100 D101\nLD M5\nOUT Y7\nLD M8000\nINC D0\n";

/// The Python modules the clients need (module, package).
const PACKAGES: [(&str, &str); 3] = [
    ("pymcprotocol", "pymcprotocol"),
    ("slmp", "slmp-connect-python"),
    ("fx3u_mcprotocol", "fx3u-mcprotocol"),
];

/// Installs the client packages; false (and a printed skip) where one
/// cannot be.
fn clients_installed(test: &str) -> bool {
    for (module, package) in PACKAGES {
        if let Err(why) = ensure_python_module(module, package) {
            skip(test, &why);
            return false;
        }
    }
    true
}

fn start() -> Server {
    Server::start_program(PROGRAM, &["--melsec", "127.0.0.1:0", "--melsec-udp"])
}

/// Runs `client` with `variant` against `server`: what it saw.
fn run(server: &Server, client: &str, variant: &str) -> serde_json::Value {
    let script = server.dir.path().join("melsec_clients.py");
    std::fs::write(&script, CLIENTS).unwrap();
    let port = server.melsec.expect("a MELSEC address").port().to_string();
    let output = std::process::Command::new("python3")
        .arg(&script)
        .args([client, variant, &port])
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        output.status.success(),
        "{client} {variant} failed: {stdout}{}",
        String::from_utf8_lossy(&output.stderr)
    );
    serde_json::from_str(stdout.lines().last().unwrap_or("")).unwrap_or_else(|e| panic!("{e}: {stdout}"))
}

#[test]
fn pymcprotocol_in_3e_and_4e_frames_binary_and_ascii() {
    if !clients_installed("pymcprotocol_in_3e_and_4e_frames_binary_and_ascii") {
        return;
    }
    for variant in ["3e-binary-Q", "3e-ascii-Q", "3e-binary-iQ-R", "4e-ascii-iQ-R"] {
        let server = start();
        let seen = run(&server, "pymcprotocol", variant);
        let expected = serde_json::json!({
            "D101": 1234, "Y7": 1, "Y0": 1,
            "random": [[-5, 1234], [70000]],
            "model": ["FX3U-LADDERC", if variant.contains("ascii") { "00F3" } else { "00f3" }],
            "echo": [8, "0123ABCD"],
            "Y0_stopped": 0, "Y0_run": 1,
            "beyond": "mc protocol error: error code 0xC056",
        });
        assert_eq!(seen, expected, "{variant}");
    }
}

#[test]
fn slmp_connect_python_over_tcp_and_udp_in_3e_and_4e_frames() {
    if !clients_installed("slmp_connect_python_over_tcp_and_udp_in_3e_and_4e_frames") {
        return;
    }
    for variant in ["tcp-iq-f", "udp-iq-f", "tcp-iq-f-4e", "tcp-iq-r"] {
        let server = start();
        let seen = run(&server, "slmp", variant);
        let expected = serde_json::json!({
            "D101": 4321, "Y7": true, "Y0": true,
            "state_stopped": "Stop", "Y0_stopped": false,
            "state_run": "Run", "Y0_run": true, "state_paused": "Pause",
            "model": "FX3U-LADDERC", "echo": "0123ABCD",
            "beyond": "0xc056",
        });
        assert_eq!(seen, expected, "{variant}");
    }
}

#[test]
fn what_one_client_writes_the_others_and_modbus_read_back_through_the_program() {
    let test = "what_one_client_writes_the_others_and_modbus_read_back_through_the_program";
    if !clients_installed(test) {
        return;
    }
    let server = start();
    let mut modbus = modbus_connect(server.address);
    // pymcprotocol (3E) writes D100 = 1234, M5 and X0 ON.
    run(&server, "pymcprotocol", "3e-binary-Q:write");
    // fx3u-mcprotocol (1E ASCII) reads them, and what the program made of them.
    let seen = run(&server, "fx3u", "ascii");
    assert_eq!(
        seen,
        serde_json::json!({"D100": [1234, 1234], "Y": [1, 0, 0, 0, 0, 0, 0, 1], "M5": 1, "X0": 1})
    );
    assert_eq!(
        modbus_request(&mut modbus, &[0x03, 0, 101, 0, 1]),
        [0x03, 2, 0x04, 0xD2]
    );
    // slmp-connect-python (3E, iQ-F) writes D100 = 4321: Modbus and 1E see it.
    run(&server, "slmp", "tcp-iq-f:write");
    assert_eq!(
        modbus_request(&mut modbus, &[0x03, 0, 101, 0, 1]),
        [0x03, 2, 0x10, 0xE1]
    );
    assert_eq!(run(&server, "fx3u", "ascii")["D100"], serde_json::json!([4321, 4321]));
    // fx3u-mcprotocol's binary mode cannot talk to an FX3U-ENET-ADP: it
    // sends the device name before the head device number and reads the
    // first data word as the end code (fx3u_mcprotocol/protocol_binary.py),
    // so it is not run here.
    skip(
        test,
        "fx3u-mcprotocol in binary: the client puts the device name before the number (not the 1E layout)",
    );
}
