"""The closed loop of docs/cosimulation.md, run by FMPy's SSP master:

    python3 tank_loop.py tank.fmu TankPlant.fmu [SECONDS]

packs SystemStructure.ssd (beside this file) with the two FMUs into
tank_loop.ssp, simulates it in 0.1 s steps, and prints one JSON object: the
level, the valves and the switches at every step.
"""
import json
import os
import sys
import zipfile

from fmpy.ssp.simulation import simulate_ssp

controller, plant = sys.argv[1], sys.argv[2]
seconds = float(sys.argv[3]) if len(sys.argv) > 3 else 20.0
here = os.path.dirname(os.path.abspath(__file__))
ssp = os.path.join(os.path.dirname(os.path.abspath(controller)), "tank_loop.ssp")
with zipfile.ZipFile(ssp, "w") as archive:
    archive.write(os.path.join(here, "SystemStructure.ssd"), "SystemStructure.ssd")
    archive.write(controller, "resources/tank.fmu")
    archive.write(plant, "resources/TankPlant.fmu")
result = simulate_ssp(ssp, stop_time=seconds, step_size=0.1)
print(json.dumps({
    "time": [round(float(t), 3) for t in result["time"]],
    "level": [round(float(v), 4) for v in result["plant.level"]],
    "inlet": [int(v) for v in result["plc.Y0"]],
    "outlet": [int(v) for v in result["plc.Y1"]],
}))
