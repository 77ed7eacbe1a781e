# MELSEC clients from PyPI against `ladderc serve --melsec`, driven by
# compiler/tests/serve/serve_melsec_clients.rs. Usage:
#   python3 melsec_clients.py CLIENT VARIANT PORT
# CLIENT: pymcprotocol | slmp | fx3u. Prints one JSON object of what it saw.
#
# The program: X0 seals Y0 in (X1 resets), D101 follows D100, Y7 follows M5.
import json
import sys
import time

client_name, variant, port = sys.argv[1], sys.argv[2], int(sys.argv[3])
# VARIANT:write only writes (D100, M5, X0) and waits until the program has
# seen them; the rest switches RUN/STOP, which clears what is not latched.
only_write = variant.endswith(":write")
variant = variant.removesuffix(":write")
host = "127.0.0.1"
seen = {}


def done():
    print(json.dumps(seen, default=str))
    sys.exit(0)


def until(read, want, seconds=5.0):
    """Reads until `want` comes back (a scan or two), returns the last."""
    deadline = time.time() + seconds
    value = read()
    while value != want and time.time() < deadline:
        time.sleep(0.02)
        value = read()
    return value


if client_name == "pymcprotocol":
    import pymcprotocol

    frame, code, plctype = variant.split("-", 2)
    mc = pymcprotocol.Type4E(plctype=plctype) if frame == "4e" else pymcprotocol.Type3E(plctype=plctype)
    mc.setaccessopt(commtype=code)
    mc.connect(host, port)
    mc.batchwrite_wordunits(headdevice="D100", values=[1234])
    seen["D101"] = until(lambda: mc.batchread_wordunits(headdevice="D101", readsize=1)[0], 1234)
    mc.batchwrite_bitunits(headdevice="M5", values=[1])
    seen["Y7"] = until(lambda: mc.batchread_bitunits(headdevice="Y0", readsize=8)[7], 1)
    mc.batchwrite_bitunits(headdevice="X0", values=[1])
    seen["Y0"] = until(lambda: mc.batchread_bitunits(headdevice="Y0", readsize=1)[0], 1)
    if only_write:
        done()
    mc.randomwrite(word_devices=["D102"], word_values=[-5], dword_devices=["D110"], dword_values=[70000])
    # Writes take effect at the next scan: read until they have.
    seen["random"] = until(lambda: mc.randomread(word_devices=["D102", "D101"], dword_devices=["D110"]),
                           ([-5, 1234], [70000]))
    seen["model"] = list(mc.read_cputype())
    seen["echo"] = list(mc.echo_test("0123ABCD"))
    mc.remote_stop()
    seen["Y0_stopped"] = until(lambda: mc.batchread_bitunits(headdevice="Y0", readsize=1)[0], 0)
    mc.remote_run(clear_mode=0)
    seen["Y0_run"] = until(lambda: mc.batchread_bitunits(headdevice="Y0", readsize=1)[0], 1)
    try:
        mc.batchread_wordunits(headdevice="D8600", readsize=1)
        seen["beyond"] = "answered"
    except Exception as error:  # pymcprotocol raises MCProtocolError with the end code
        seen["beyond"] = str(error)
    mc.close()
elif client_name == "slmp":
    from slmp import SlmpClient, SlmpError

    transport, profile = variant.split("-", 1)
    if profile == "iq-f-4e":
        # The iQ-F's device numbering (octal X/Y) in 4E frames: the
        # low-level route of the same client.
        client = SlmpClient(host, port, transport=transport, frame_type="4e", plc_series="ql",
                            address_profile="melsec:iq-f", _allow_manual_profile=True)
    else:
        client = SlmpClient(host, port, transport=transport, plc_profile="melsec:" + profile)
    with client as plc:
        plc.write_devices("D100", [4321])
        seen["D101"] = until(lambda: plc.read_devices("D101", 1)[0], 4321)
        if only_write:
            done()
        plc.write_devices("M5", [True], bit_unit=True)
        seen["Y7"] = until(lambda: bool(plc.read_devices("Y0", 8, bit_unit=True)[7]), True)
        # X10 is the ninth input on an FX: octal numbers (the iQ-F profile).
        plc.write_devices("X0", [True], bit_unit=True)
        seen["Y0"] = until(lambda: bool(plc.read_devices("Y0", 1, bit_unit=True)[0]), True)
        plc.remote_stop()
        seen["state_stopped"] = plc.read_cpu_operation_state().status.name
        seen["Y0_stopped"] = until(lambda: bool(plc.read_devices("Y0", 1, bit_unit=True)[0]), False)
        plc.remote_run(force=False, clear_mode=0)
        seen["state_run"] = plc.read_cpu_operation_state().status.name
        seen["Y0_run"] = until(lambda: bool(plc.read_devices("Y0", 1, bit_unit=True)[0]), True)
        plc.remote_pause(force=False)
        seen["state_paused"] = plc.read_cpu_operation_state().status.name
        plc.remote_run(force=False, clear_mode=0)
        seen["model"] = plc.read_type_name().model
        seen["echo"] = plc.self_test_loopback("0123ABCD").decode()
        try:
            plc.read_devices("D8600", 1)
            seen["beyond"] = "answered"
        except SlmpError as error:
            seen["beyond"] = hex(error.end_code or 0)
elif client_name == "fx3u":
    from fx3u_mcprotocol import FX3UClient

    plc = FX3UClient(host, port=port, cpu="FX3U", mode=variant, timeout=5.0)
    plc.connect()
    seen["D100"] = plc.readRegs("D100", 2)
    seen["Y"] = [int(bool(v)) for v in plc.readBits("Y0", 8)]
    seen["M5"] = int(bool(plc.readBits("M5", 1)[0]))
    seen["X0"] = int(bool(plc.readBits("X0", 1)[0]))
    plc.close()
else:
    raise SystemExit("unknown client " + client_name)

done()
