# FMPy against FMUs built by `ladderc build --emit fmu`, driven by
# compiler/tests/commands/fmu_export.rs. Usage:
#   python3 fmpy_checks.py validate FMU...     problems fmpy validate finds
#   python3 fmpy_checks.py lamps FMU STEPS     Y0-Y2 after each 0.1 s step
#   python3 fmpy_checks.py seal_in FMU         Y0 under an input signal
#   python3 fmpy_checks.py state FMU           the FMU state saved and restored
#   python3 fmpy_checks.py wide FMU            pairs and reals set and read
#   python3 fmpy_checks.py causality FMU       each variable's causality
# Each prints one JSON value.
import json
import sys

import numpy as np
from fmpy import extract, read_model_description, simulate_fmu
from fmpy.validation import validate_fmu

command, args = sys.argv[1], sys.argv[2:]

if command == "validate":
    print(json.dumps({fmu: [str(p) for p in validate_fmu(fmu)] for fmu in args}))
elif command == "lamps":
    fmu, steps = args[0], int(args[1])
    result = simulate_fmu(fmu, stop_time=steps * 0.1, output_interval=0.1, output=["Y0", "Y1", "Y2"])
    # Row k is after step k (row 0: before any).
    print(json.dumps([[int(row["Y0"]), int(row["Y1"]), int(row["Y2"])] for row in result[1:]]))
elif command == "seal_in":
    fmu = args[0]
    signal = np.array(
        [(0.0, False, False), (0.2, True, False), (0.3, False, False), (0.6, False, True), (0.7, False, False)],
        dtype=[("time", np.float64), ("X0", np.bool_), ("X1", np.bool_)],
    )
    result = simulate_fmu(fmu, stop_time=1.0, output_interval=0.01, input=signal, output=["Y0"])
    print(json.dumps([[round(float(row["time"]), 3), int(row["Y0"])] for row in result]))
elif command == "causality":
    description = read_model_description(args[0])
    print(json.dumps({v.name: v.causality for v in description.modelVariables}))
elif command == "wide":
    fmu = args[0]
    outputs = ["D10:32", "D22:float", "D10", "D11"]
    result = simulate_fmu(fmu, stop_time=0.03, output_interval=0.01, output=outputs,
                          start_values={"D0:32": 100000, "D20:float": 2.25})
    print(json.dumps({name: float(result[-1][name]) for name in outputs}))
elif command == "state":
    fmu = args[0]
    description = read_model_description(fmu)
    unzipped = extract(fmu)
    vr = {v.name: v.valueReference for v in description.modelVariables}
    lamps = [vr["Y0"], vr["Y1"], vr["Y2"]]
    if description.fmiVersion.startswith("3"):
        from fmpy.fmi3 import FMU3Slave as Slave

        slave = Slave(guid=description.guid, unzipDirectory=unzipped,
                      modelIdentifier=description.coSimulation.modelIdentifier, instanceName="plc")
        slave.instantiate()
        slave.setFloat64([vr["scan_period"]], [0.1])
        slave.enterInitializationMode()
        slave.exitInitializationMode()
        get_state, set_state = slave.getFMUState, slave.setFMUState
        serialize, deserialize = slave.serializeFMUState, slave.deserializeFMUState
    else:
        from fmpy.fmi2 import FMU2Slave as Slave

        slave = Slave(guid=description.guid, unzipDirectory=unzipped,
                      modelIdentifier=description.coSimulation.modelIdentifier, instanceName="plc")
        slave.instantiate()
        slave.setReal([vr["scan_period"]], [0.1])
        slave.setupExperiment(startTime=0.0)
        slave.enterInitializationMode()
        slave.exitInitializationMode()
        get_state, set_state = slave.getFMUstate, slave.setFMUstate
        serialize, deserialize = slave.serializeFMUstate, slave.deSerializeFMUstate
    time = [0.0]

    def run(steps):
        seen = []
        for _ in range(steps):
            slave.doStep(time[0], 0.1)
            time[0] += 0.1
            seen.append([int(v) for v in slave.getBoolean(lamps)])
        return seen

    run(28)
    saved = get_state()
    first = run(10)
    set_state(saved)
    time[0] = 2.8
    again = run(10)
    restored = deserialize(serialize(saved))
    set_state(restored)
    time[0] = 2.8
    from_bytes = run(10)
    # A step of 0.05 s with 0.1 s scans carries over: two such steps are one scan.
    set_state(saved)
    half = []
    for n in range(6):
        slave.doStep(2.8 + n * 0.05, 0.05)
        half.append([int(v) for v in slave.getBoolean(lamps)])
    # Bytes that are not this FMU's state are refused.
    foreign = bytearray(serialize(saved))
    foreign[1] ^= 0x20
    try:
        deserialize(bytes(foreign))
        foreign_state = "taken"
    except Exception:
        foreign_state = "refused"
    slave.terminate()
    slave.freeInstance()
    print(json.dumps({"first": first, "again": again, "from_bytes": from_bytes, "half_steps": half,
                      "foreign_state": foreign_state}))
else:
    raise SystemExit("unknown command " + command)
