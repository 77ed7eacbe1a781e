//! `ladderc serve --opcua`, driven by an independent OPC UA client (the
//! Python `asyncua` package from PyPI, installed when missing; the test
//! says it skipped where it cannot be): it browses Objects/PLC, reads
//! devices with their data types, writes an input and sees a timer count
//! through a subscription, writes 32-bit and float pairs and reads them
//! back over HTTP; `--read-only` and `--token-file` refuse anonymous writes
//! and the token's user writes; a read is not held up by a write waiting
//! for the end of a scan.

use crate::common::server::{http, json, slow_program, Server};
use crate::common::tools::{ensure_python_module, skip};

/// X0 times T0 (100 ms units); D0 counts scans.
const PROGRAM: &str = "LD X0\nOUT T0 K1000\nLD M8000\nINC D0\nLD X1\nOUT Y0\n";

/// The client: prints one JSON object of what it saw.
const CLIENT: &str = r#"
import asyncio, json, sys
from asyncua import Client, ua

async def write(node, value, kind):
    try:
        await node.write_value(ua.DataValue(ua.Variant(value, kind)))
        return "Good"
    except ua.UaStatusCodeError as e:
        return type(e).__name__

async def main(url, user, password):
    client = Client(url)
    if user:
        client.set_user(user)
        client.set_password(password)
    out = {}
    async with client:
        ns = await client.get_namespace_index("urn:ladderc:plc")
        plc = await client.nodes.objects.get_child([f"{ns}:PLC"])
        out["folders"] = sorted([(await f.read_browse_name()).Name for f in await plc.get_children()])
        node = lambda name: client.get_node(f"ns={ns};s={name}")
        out["types"] = {}
        for name in ["X0", "D0", "D10:32", "D20:float", "TN0", "T0", "C0"]:
            out["types"][name] = (await node(name).read_data_type_as_variant_type()).name
        out["D0"] = await node("D0").read_value()
        out["write_X0"] = await write(node("X0"), True, ua.VariantType.Boolean)
        out["write_D10"] = await write(node("D10:32"), 100000, ua.VariantType.Int32)
        out["write_D20"] = await write(node("D20:float"), 2.5, ua.VariantType.Float)
        out["write_D30_wrong_type"] = await write(node("D30"), "text", ua.VariantType.String)
        seen = []
        class Handler:
            def datachange_notification(self, node, value, data):
                seen.append(value)
        subscription = await client.create_subscription(20, Handler())
        await subscription.subscribe_data_change(node("TN0"), sampling_interval=10)
        await asyncio.sleep(1.0)
        out["TN0_seen"] = seen
        out["D10"] = await node("D10:32").read_value()
        out["D20"] = await node("D20:float").read_value()
    print(json.dumps(out))

asyncio.run(main(sys.argv[1], sys.argv[2] if len(sys.argv) > 2 else None, sys.argv[3] if len(sys.argv) > 3 else None))
"#;

/// Runs the client against `server`; None (and a printed skip) where the
/// client cannot be installed.
fn client(test: &str, server: &Server, user: Option<(&str, &str)>) -> Option<serde_json::Value> {
    if let Err(why) = ensure_python_module("asyncua", "asyncua") {
        skip(test, &why);
        return None;
    }
    let script = server.dir.path().join("client.py");
    std::fs::write(&script, CLIENT).unwrap();
    let opcua = opcua_address(server);
    let mut command = std::process::Command::new("python3");
    command.arg(&script).arg(format!("opc.tcp://{opcua}/"));
    if let Some((name, password)) = user {
        command.args([name, password]);
    }
    let output = command.output().unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        output.status.success(),
        "client failed: {stdout}{}",
        String::from_utf8_lossy(&output.stderr)
    );
    Some(json(stdout.lines().last().unwrap_or("")))
}

/// The OPC UA port: chosen by the test (the helper reads Modbus and HTTP
/// lines only), free when the server started.
fn opcua_address(server: &Server) -> std::net::SocketAddr {
    server.opcua.expect("started with --opcua")
}

fn start(extra: &[&str]) -> Server {
    // Port 0: the server binds a free port and says which before it serves
    // (a port picked free here could be taken by another test meanwhile).
    let mut args = vec!["--http", "127.0.0.1:0", "--opcua", "127.0.0.1:0", "--opcua-devices"];
    args.push("X0..X7,Y0..Y7,T0,TN0,C0,D0..D9,D10:32,D20:float,D30");
    args.extend_from_slice(extra);
    Server::start_program(PROGRAM, &args)
}

#[test]
fn an_opcua_client_browses_reads_writes_and_subscribes() {
    let server = start(&[]);
    let Some(seen) = client("an_opcua_client_browses_reads_writes_and_subscribes", &server, None) else {
        return;
    };
    assert_eq!(
        seen["folders"],
        serde_json::json!(["C", "D", "T", "TN", "X", "Y"]),
        "{seen}"
    );
    assert_eq!(seen["types"]["X0"], "Boolean", "{seen}");
    assert_eq!(seen["types"]["D0"], "Int16", "{seen}");
    assert_eq!(seen["types"]["D10:32"], "Int32", "{seen}");
    assert_eq!(seen["types"]["D20:float"], "Float", "{seen}");
    // A timer's and a counter's contact are T0 and C0, as the docs name them.
    assert_eq!(seen["types"]["T0"], "Boolean", "{seen}");
    assert_eq!(seen["types"]["C0"], "Boolean", "{seen}");
    assert!(seen["D0"].as_i64().unwrap() > 0, "D0 counts scans: {seen}");
    for write in ["write_X0", "write_D10", "write_D20"] {
        assert_eq!(seen[write], "Good", "{write}: {seen}");
    }
    assert_eq!(seen["write_D30_wrong_type"], "BadTypeMismatch", "{seen}");
    // The subscription saw T0 count in real time after X0 went ON.
    let counts: Vec<i64> = seen["TN0_seen"]
        .as_array()
        .unwrap()
        .iter()
        .filter_map(|v| v.as_i64())
        .collect();
    assert!(counts.len() >= 5, "{seen}");
    assert!(counts.windows(2).all(|w| w[0] <= w[1]), "a timer counts up: {counts:?}");
    assert!(counts.last().unwrap() - counts.first().unwrap() >= 5, "{counts:?}");
    assert_eq!(seen["D10"], 100000, "{seen}");
    assert_eq!(seen["D20"], 2.5, "{seen}");
    // The same devices over HTTP: the pair's words, low word first.
    let web = server.web.unwrap();
    let devices = json(&http(web, "GET", "/api/devices?watch=D10,D11,X0", "").1);
    assert_eq!(
        devices["devices"]["D10"],
        i64::from((100_000 & 0xFFFF) as u16 as i16),
        "{devices}"
    );
    assert_eq!(devices["devices"]["D11"], 1, "{devices}");
    assert_eq!(devices["devices"]["X0"], 1, "{devices}");
    server.stop();
}

#[test]
fn read_only_and_token_servers_refuse_anonymous_writes() {
    let server = start(&["--read-only"]);
    let Some(seen) = client("read_only_and_token_servers_refuse_anonymous_writes", &server, None) else {
        return;
    };
    assert_ne!(seen["write_X0"], "Good", "{seen}");
    assert_ne!(seen["write_D10"], "Good", "{seen}");
    assert_eq!(seen["D0"].as_i64().map(|d| d > 0), Some(true), "reads go on: {seen}");
    server.stop();

    let dir = tempfile::tempdir().unwrap();
    let token = "0123456789abcdef0123";
    let file = dir.path().join("token");
    std::fs::write(&file, token).unwrap();
    let server = start(&["--token-file", file.to_str().unwrap()]);
    let anonymous = client("read_only_and_token_servers_refuse_anonymous_writes", &server, None).unwrap();
    assert_eq!(anonymous["write_X0"], "BadUserAccessDenied", "{anonymous}");
    let operator = client(
        "read_only_and_token_servers_refuse_anonymous_writes",
        &server,
        Some(("operator", token)),
    )
    .unwrap();
    assert_eq!(operator["write_X0"], "Good", "{operator}");
    assert_eq!(operator["D10"], 100000, "{operator}");
    server.stop();
}

/// The client of `a_read_is_not_held_up_by_a_write_waiting_for_a_scan`:
/// each round writes D100 and, 5 ms later on the same session, reads D0;
/// how many reads were answered within 30 ms while their write still
/// waited (answered 10 ms after the read or later), whether D100 reads
/// back after the write's answer, and a write of two nodes in one request
/// read back.
const WAITING_CLIENT: &str = r#"
import asyncio, json, sys, time
from asyncua import Client, ua

async def main(url, rounds):
    client = Client(url)
    out = {"quick_reads": 0, "misses": 0}
    async with client:
        ns = await client.get_namespace_index("urn:ladderc:plc")
        node = lambda name: client.get_node(f"ns={ns};s={name}")
        for value in range(1, rounds + 1):
            done, began = {}, time.monotonic()
            async def write():
                await node("D100").write_value(ua.DataValue(ua.Variant(value, ua.VariantType.Int16)))
                done["write"] = time.monotonic()
            async def read():
                await asyncio.sleep(0.005)
                await node("D0").read_value()
                done["read"] = time.monotonic()
            await asyncio.gather(write(), read())
            quick = done["read"] - began - 0.005 < 0.030
            out["quick_reads"] += quick and done["write"] - done["read"] >= 0.010
            out["misses"] += await node("D100").read_value() != value
        values = [ua.DataValue(ua.Variant(v, ua.VariantType.Int16)) for v in (7, 8)]
        await client.write_values([node("D101"), node("D102")], values)
        out["pair"] = [await node("D101").read_value(), await node("D102").read_value()]
    print(json.dumps(out))

asyncio.run(main(sys.argv[1], int(sys.argv[2])))
"#;

/// A write waits for the end of the scan in progress without holding the
/// address space: with scans back to back of some 80 ms, a read sent
/// while a write waits is answered at once most times (async-opcua's
/// simple node manager waited under its write lock, and a read was
/// answered only after the write, often some 40 ms after it); each write
/// reads back once answered.
#[test]
fn a_read_is_not_held_up_by_a_write_waiting_for_a_scan() {
    let test = "a_read_is_not_held_up_by_a_write_waiting_for_a_scan";
    if let Err(why) = ensure_python_module("asyncua", "asyncua") {
        skip(test, &why);
        return;
    }
    let program = slow_program(std::time::Duration::from_millis(80));
    let server = Server::start_program(
        &program,
        &[
            "--opcua",
            "127.0.0.1:0",
            "--opcua-devices",
            "D0..D199",
            "--scan-ms",
            "10",
            "--engine",
            "interp",
        ],
    );
    let script = server.dir.path().join("waiting.py");
    std::fs::write(&script, WAITING_CLIENT).unwrap();
    let output = std::process::Command::new("python3")
        .arg(&script)
        .arg(format!("opc.tcp://{}/", opcua_address(&server)))
        .arg("20")
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        output.status.success(),
        "client failed: {stdout}{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let seen = json(stdout.lines().last().unwrap_or(""));
    println!("{test}: {seen}");
    assert_eq!(seen["misses"], 0, "every write reads back once answered: {seen}");
    assert_eq!(seen["pair"], serde_json::json!([7, 8]), "{seen}");
    assert!(seen["quick_reads"].as_u64().unwrap_or(0) >= 8, "{seen}");
}
