# A remote I/O module for compiler/tests/serve/serve_remote_io.rs: pymodbus's
# server (Modbus TCP, or RTU on a serial line) with 64 discrete inputs, 64
# coils, 16 input registers and 16 holding registers, and a control socket
# on which the test sets the inputs and reads the outputs, one line each:
#   di N 0|1   ir N VALUE   co N   hr N   writes   wc N
# (`co` and `hr` answer the value, `writes` how many write requests came,
# `wc N` how many of them wrote coils from address N).
# Usage: python3 module.py tcp PORT CONTROL_PORT | rtu TTY CONTROL_PORT
# Prints `ready` once both listen (the Modbus port answers a connection,
# the serial line is open).
import asyncio
import os
import sys

from pymodbus.server import StartAsyncSerialServer, StartAsyncTcpServer

state = {"d": [0] * 64, "c": [0] * 64, "i": [0] * 16, "h": [0] * 16, "writes": 0, "wc": [0] * 64}
TABLE = {1: "c", 5: "c", 15: "c", 2: "d", 3: "h", 6: "h", 16: "h", 4: "i"}


async def action(function_code, start_address, address, count, registers, set_values):
    """Serves every request from `state` (reads) or into it (writes)."""
    name = TABLE[function_code]
    table = state[name]
    if set_values is None and name in "cd":
        # pymodbus 3.16's simulator (bit addressing): bit `address` is bit
        # `address % 16` of register `address // 16`; `count` counts
        # registers here.
        from pymodbus.simulator.simutils import SimUtils

        first = address % 16
        bits = [False] * (16 * count)
        for k in range(16 * count - first):
            bits[first + k] = bool(table[address + k]) if address + k < len(table) else False
        offset = address // 16 - start_address
        registers[offset : offset + len(bits) // 16] = SimUtils.bitsToRegisters(bits)
    elif set_values is None:
        for k in range(count):
            registers[address - start_address + k] = int(table[address + k])
    else:
        state["writes"] += 1
        if name == "c":
            state["wc"][address] += 1
        for k, value in enumerate(set_values):
            table[address + k] = int(bool(value)) if name in "cd" else int(value)
    return None


def device():
    from pymodbus.simulator import DataType, SimData, SimDevice

    bits = lambda: [SimData(0, count=80 * 16, values=False, datatype=DataType.BITS)]
    words = lambda: [SimData(0, count=16, values=0, datatype=DataType.REGISTERS)]
    return SimDevice(id=0, simdata=(bits(), bits(), words(), words()), use_bit_addressing=True, action=action)


async def control(reader, writer):
    while line := (await reader.readline()).decode().split():
        what = line[0]
        if what in ("di", "ir"):
            state[what[0]][int(line[1])] = int(line[2])
            answer = "ok"
        elif what in ("co", "hr"):
            answer = str(state[what[0]][int(line[1])])
        elif what == "wc":
            answer = str(state["wc"][int(line[1])])
        else:
            answer = str(state["writes"])
        writer.write((answer + "\n").encode())
        await writer.drain()
    writer.close()


async def main():
    mode, where, control_port = sys.argv[1], sys.argv[2], int(sys.argv[3])
    await asyncio.start_server(control, "127.0.0.1", control_port)
    if mode == "tcp":
        server = StartAsyncTcpServer(device(), address=("127.0.0.1", int(where)))
    else:
        from pymodbus import FramerType

        server = StartAsyncSerialServer(
            device(), port=where, framer=FramerType.RTU, baudrate=115200, bytesize=8, parity="N", stopbits=1
        )
    task = asyncio.create_task(server)
    while not await listening(mode, where):
        if task.done():
            task.result()
        await asyncio.sleep(0.01)
    print("ready", flush=True)
    await task


async def listening(mode, where):
    """Whether the Modbus server takes requests: its TCP port accepts a
    connection, or this process holds the serial line open."""
    if mode == "tcp":
        try:
            _, writer = await asyncio.open_connection("127.0.0.1", int(where))
        except OSError:
            return False
        writer.close()
        return True
    line = os.path.realpath(where)
    for fd in os.listdir("/proc/self/fd"):
        try:
            if os.path.realpath(f"/proc/self/fd/{fd}") == line:
                return True
        except OSError:
            pass
    return False


asyncio.run(main())
