# pymodbus's serial client against `ladderc serve --modbus-rtu`, driven by
# compiler/tests/serve/serve_modbus_rtu.rs. Usage:
#   python3 modbus_rtu_client.py TTY UNIT
# The program: D101 follows D100, Y7 follows M5. Prints one JSON object.
import json
import sys
import time

import serial
from pymodbus.client import ModbusSerialClient

port, unit = sys.argv[1], int(sys.argv[2])
seen = {}
# 8N1: a pty pair (socat) refuses some parity settings with a timeout.
FORMAT = dict(baudrate=19200, bytesize=8, parity="N", stopbits=1)


def unit_kw(n):
    """pymodbus names the unit `device_id` (3.10 on) or `slave` (before)."""
    import inspect
    names = inspect.signature(ModbusSerialClient.read_holding_registers).parameters
    return {"device_id": n} if "device_id" in names else {"slave": n}


def until(read, want, seconds=5.0):
    deadline = time.time() + seconds
    value = read()
    while value != want and time.time() < deadline:
        time.sleep(0.05)
        value = read()
    return value


def register(client, address, n=unit):
    response = client.read_holding_registers(address, count=1, **unit_kw(n))
    return None if response.isError() else response.registers[0]


client = ModbusSerialClient(port, timeout=1, retries=0, **FORMAT)
assert client.connect(), "the client opens the line"
client.write_register(100, 1234, **unit_kw(unit))
seen["D101"] = until(lambda: register(client, 101), 1234)
client.write_coil(1005, True, **unit_kw(unit))
seen["Y7"] = until(lambda: client.read_coils(7, count=1, **unit_kw(unit)).bits[0], True)
# Another unit's request gets no answer (pymodbus reports no response).
try:
    other = client.read_holding_registers(101, count=1, **unit_kw(unit + 1))
    seen["other_unit"] = "error" if other.isError() else other.registers
except Exception as error:
    seen["other_unit"] = type(error).__name__
client.close()


def crc(frame):
    value = 0xFFFF
    for byte in frame:
        value ^= byte
        for _ in range(8):
            value = (value >> 1) ^ 0xA001 if value & 1 else value >> 1
    return bytes([value & 0xFF, value >> 8])


# Raw frames on the line: a bad CRC is ignored, the next frame is answered;
# a broadcast write is carried out and answered by nobody.
line = serial.Serial(port, timeout=0.5, **FORMAT)
request = bytes([unit, 0x03, 0x00, 101, 0x00, 0x01])
line.write(request + bytes([0x00, 0x00]))
seen["bad_crc_answer"] = line.read(16).hex()
line.write(request + crc(request))
answer = line.read(7)
seen["next_answer"] = answer.hex()
seen["next_answer_crc_ok"] = len(answer) == 7 and crc(answer[:5]) == answer[5:]
broadcast = bytes([0x00, 0x06, 0x00, 102, 0x00, 77])
line.write(broadcast + crc(broadcast))
seen["broadcast_answer"] = line.read(16).hex()
line.close()
client = ModbusSerialClient(port, timeout=1, retries=0, **FORMAT)
client.connect()
seen["D102"] = until(lambda: register(client, 102), 77)
client.close()
print(json.dumps(seen))
