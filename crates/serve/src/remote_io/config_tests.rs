//! Tests of the remote I/O file: a complete file parsed, defaults, errors
//! naming their line, and ranges split within Modbus's limits.

use super::*;

const FILE: &str = r#"
[[device]]
name = "rack1"
tcp = "127.0.0.1:1502"
unit = 3
period_ms = 20
timeout_ms = 50
retries = 1
on_loss = "clear"
status = "M100"
errors = "D100"

[[device.input]]
discrete_inputs = 0
count = 16
to = "X0"

[[device.input]]
input_registers = 10
count = 2
to = "D10"

[[device.output]]
coils = 0
count = 8
from = "Y0"

[[device.output]]
holding_registers = 0
count = 300
from = "D200"

[[device]]
rtu = "/dev/ttyUSB0:9600,8N1"

[[device.input]]
discrete_inputs = 0
count = 8
to = "X20"
"#;

#[test]
fn a_complete_file_is_read_with_its_defaults() {
    let io = parse(FILE).unwrap();
    assert_eq!(io.devices.len(), 2);
    let rack = &io.devices[0];
    assert_eq!(rack.name, "rack1");
    assert_eq!(rack.link, Link::Tcp("127.0.0.1:1502".parse().unwrap()));
    assert_eq!((rack.unit, rack.retries, rack.on_loss), (3, 1, OnLoss::Clear));
    assert_eq!(rack.period, Duration::from_millis(20));
    assert_eq!(
        rack.keepalive,
        Duration::from_millis(20),
        "the keep-alive defaults to the period"
    );
    assert_eq!((rack.status, rack.errors), (100, 100));
    assert_eq!(
        rack.inputs[0],
        Input {
            table: InputTable::DiscreteInputs,
            address: 0,
            count: 16,
            to: 0
        }
    );
    assert_eq!(rack.outputs[1].from, Source::Words(200));
    let second = &io.devices[1];
    assert_eq!(second.name, "device2");
    assert_eq!(
        second.link,
        Link::Rtu {
            path: "/dev/ttyUSB0".into(),
            format: ladder_modbus::rtu::Format::parse("9600,8N1").unwrap()
        }
    );
    assert_eq!((second.unit, second.retries, second.on_loss), (1, 2, OnLoss::Hold));
    assert_eq!(second.period, Duration::from_millis(100));
    assert_eq!((second.status, second.errors), (DEFAULT_STATUS + 1, DEFAULT_ERRORS + 1));
    // X20 is octal: the 17th input.
    assert_eq!(second.inputs[0].to, 16);
}

#[test]
fn errors_name_their_line() {
    let cases = [
        (
            "[[device]]\ntcp = \"127.0.0.1:502\"\nperiod = 5\n",
            "3:",
            "unknown field",
        ),
        ("[[device]]\nname = \"a\"\n", "1:", "needs tcp"),
        (
            "[[device]]\ntcp = \"127.0.0.1:502\"\n\n[[device.input]]\ndiscrete_inputs = 0\ncount = 8\nto = \"Y0\"\n",
            "4:",
            "not a device of X",
        ),
        (
            "[[device]]\ntcp = \"127.0.0.1:502\"\n[[device.output]]\ncoils = 65530\ncount = 8\nfrom = \"Y0\"\n",
            "3:",
            "past Modbus address 65535",
        ),
        (
            "[[device]]\ntcp = \"127.0.0.1:502\"\n[[device.input]]\ninput_registers = 0\ncount = 10\nto = \"D7995\"\n",
            "3:",
            "past the end",
        ),
        (
            "[[device]]\ntcp = \"127.0.0.1:502\"\non_loss = \"zero\"\n",
            "1:",
            "on_loss is",
        ),
        (
            "[[device]]\ntcp = \"127.0.0.1:502\"\n[[device.input]]\ndiscrete_inputs = 0\ncount = 8\nto = \"X0\"\n\
             [[device]]\ntcp = \"127.0.0.1:503\"\n[[device.input]]\ndiscrete_inputs = 0\ncount = 8\nto = \"X4\"\n",
            "7:",
            "writes X4 which `device1` writes too",
        ),
        (
            "[[device]]\nrtu = \"/dev/ttyS9\"\n[[device]]\nrtu = \"/dev/ttyS9\"\n",
            "3:",
            "has the unit id of `device1` on the same serial line",
        ),
        (
            "[[device]]\nrtu = \"/dev/ttyS9:9600,8N1\"\n[[device]]\nrtu = \"/dev/ttyS9:19200,8N1\"\nunit = 2\n",
            "3:",
            "with another format",
        ),
        (
            "[[device]]\ntcp = \"127.0.0.1:502\"\nperiod_ms = 100\nkeepalive_ms = 50\n",
            "1:",
            "keepalive_ms (50) is less than period_ms (100)",
        ),
        (
            "[[device]]\ntcp = \"127.0.0.1:502\"\n[[device.output]]\ncoils = 0\ncount = 8\nfrom = \"Y0\"\n\
             [[device.output]]\ncoils = 7\ncount = 2\nfrom = \"M0\"\n",
            "7:",
            "writes module address 7 which the output from Y0 writes too",
        ),
        (
            "[[device]]\ntcp = \"127.0.0.1:502\"\n[[device.output]]\ncoils = 4\ncount = 8\nfrom = \"Y0\"\n\
             [[device]]\ntcp = \"127.0.0.1:502\"\n[[device.output]]\ncoils = 0\ncount = 5\nfrom = \"M0\"\n",
            "7:",
            "`device2` writes module address 0 of the module `device1` writes too",
        ),
        ("[[device]]\ntcp = \"127.0.0.1:502\"\nunit = 300\n", "3:", ""),
        ("", "1:", "no [[device]]"),
    ];
    for (text, line, message) in cases {
        let error = parse(text).unwrap_err();
        assert!(error.starts_with(line), "{text:?}: {error}");
        assert!(error.contains(message), "{text:?}: {error}");
    }
}

#[test]
fn too_many_devices_are_refused() {
    let text = "[[device]]\ntcp = \"127.0.0.1:502\"\nstatus = \"M0\"\nerrors = \"D0\"\n".repeat(MOST_DEVICES + 1);
    assert!(parse(&text).unwrap_err().contains("at most 64"));
}

#[test]
fn several_units_share_a_serial_line_and_outputs_to_other_tables_may_share_addresses() {
    let io = parse(
        "[[device]]\nrtu = \"/dev/ttyS9:9600,8N1\"\nunit = 1\n\
         [[device.output]]\ncoils = 0\ncount = 8\nfrom = \"Y0\"\n\
         [[device.output]]\nholding_registers = 0\ncount = 8\nfrom = \"D0\"\n\
         [[device]]\nrtu = \"/dev/ttyS9:9600,8N1\"\nunit = 2\n",
    )
    .unwrap();
    assert_eq!(io.devices.len(), 2);
    assert!(same_line(&io.devices[0], &io.devices[1]));
}

#[test]
fn the_values_a_file_maps_are_bounded() {
    // Each device its own module (port), so the outputs do not overlap.
    let device = |n: u32| {
        let port = 502 + n;
        format!(
            "[[device]]\ntcp = \"127.0.0.1:{port}\"\nstatus = \"M{n}\"\nerrors = \"D{n}\"\n\
             [[device.output]]\ncoils = 0\ncount = 2000\nfrom = \"M0\"\n"
        )
    };
    let two: String = (0..2).map(device).collect();
    assert!(parse(&two).is_ok(), "4000 values");
    let three: String = (0..3).map(device).collect();
    let error = parse(&three).unwrap_err();
    assert!(error.starts_with("17:"), "{error}");
    assert!(error.contains("6000 values so far; at most 4096"), "{error}");
}

#[test]
fn ranges_are_split_within_modbus_limits() {
    let requests: Vec<_> = split(100, 300, READ_REGISTERS).collect();
    assert_eq!(requests, [(100, 125, 0), (225, 125, 125), (350, 50, 250)]);
    let requests: Vec<_> = split(0, 2000, READ_BITS).collect();
    assert_eq!(requests, [(0, 2000, 0)]);
    let requests: Vec<_> = split(0, 2000, WRITE_BITS).collect();
    assert_eq!(requests, [(0, 1968, 0), (1968, 32, 1968)]);
    assert_eq!(split(7, 1, WRITE_REGISTERS).collect::<Vec<_>>(), [(7, 1, 0)]);
    // The last address of the table: no overflow.
    assert_eq!(
        split(65_535 - 199, 200, 123).collect::<Vec<_>>(),
        [(65_336, 123, 0), (65_459, 77, 123)]
    );
}
