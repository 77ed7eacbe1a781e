# Read-after-write through real clients against `ladderc serve`, driven by
# compiler/tests/serve/serve_read_after_write.rs. Usage:
#   python3 read_after_write.py PROTOCOL WHERE PAIRS RMWS
# PROTOCOL: modbus | rtu | melsec | http | opcua; WHERE: host:port (a tty
# for rtu). PAIRS writes of D100, each read back at once; RMWS
# read-modify-writes of bits of D300 by two clients taking turns (each
# starts after the other's write was answered), 16 to a round: after a
# round every bit is set, then D300 is cleared. Prints one JSON object:
# the reads that missed their write, the bits lost, and the rates.
import json
import sys
import time

protocol, where, pairs, rmws = sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4])


def signed(value):
    value &= 0xFFFF
    return value - 0x10000 if value >= 0x8000 else value


def modbus_clients():
    from pymodbus.client import ModbusSerialClient, ModbusTcpClient
    import inspect

    def make():
        if protocol == "rtu":
            client = ModbusSerialClient(where, timeout=2, retries=0, baudrate=115200, bytesize=8, parity="N",
                                        stopbits=1)
        else:
            host, port = where.rsplit(":", 1)
            client = ModbusTcpClient(host, port=int(port), timeout=5, retries=0)
        assert client.connect(), "the client connects"
        return client

    def unit(client):
        names = inspect.signature(client.read_holding_registers).parameters
        return {"device_id": 1} if "device_id" in names else {"slave": 1}

    class Client:
        def __init__(self, client):
            self.client, self.unit = client, unit(client)

        def write(self, register, value):
            response = self.client.write_register(register, value & 0xFFFF, **self.unit)
            assert not response.isError(), response

        def read(self, register):
            response = self.client.read_holding_registers(register, count=1, **self.unit)
            assert not response.isError(), response
            return response.registers[0]

    first = Client(make())
    # One serial line, one client on it (turns are still taken).
    return first, (first if protocol == "rtu" else Client(make()))


def melsec_clients():
    import pymcprotocol

    def make():
        host, port = where.rsplit(":", 1)
        mc = pymcprotocol.Type3E(plctype="Q")
        mc.connect(host, int(port))
        return mc

    class Client:
        def __init__(self, mc):
            self.mc = mc

        def write(self, register, value):
            self.mc.batchwrite_wordunits(headdevice=f"D{register}", values=[signed(value)])

        def read(self, register):
            return self.mc.batchread_wordunits(headdevice=f"D{register}", readsize=1)[0] & 0xFFFF

    return Client(make()), Client(make())


def http_clients():
    import http.client

    host, port = where.rsplit(":", 1)

    class Client:
        def __init__(self):
            self.connection = http.client.HTTPConnection(host, int(port), timeout=5)

        def ask(self, method, path, body=None):
            headers = {"Content-Type": "application/json"} if body is not None else {}
            self.connection.request(method, path, body=body, headers=headers)
            response = self.connection.getresponse()
            text = response.read()
            assert response.status == 200, (response.status, text)
            return json.loads(text)

        def write(self, register, value):
            self.ask("POST", "/api/set", json.dumps({"device": f"D{register}", "value": signed(value)}))

        def read(self, register):
            return self.ask("GET", f"/api/devices?watch=D{register}")["devices"][f"D{register}"] & 0xFFFF

    return Client(), Client()


def run(first, second):
    """The pairs and the read-modify-writes, with blocking clients."""
    misses = 0
    began = time.time()
    for i in range(pairs):
        value = (i * 7919 + 1) % 30000
        first.write(100, value)
        if first.read(100) != value:
            misses += 1
    pair_seconds = time.time() - began
    lost = 0
    rounds = (rmws + 15) // 16
    began = time.time()
    first.write(300, 0)
    for _ in range(rounds):
        for bit in range(16):
            client = first if bit % 2 == 0 else second
            client.write(300, client.read(300) | (1 << bit))
        lost += 16 - bin(first.read(300)).count("1")
        first.write(300, 0)
    rmw_seconds = time.time() - began
    return misses, lost, pair_seconds, rmw_seconds, rounds * 16


def run_opcua():
    import asyncio
    from asyncua import Client, ua

    async def main():
        url = f"opc.tcp://{where}/"
        async with Client(url) as a, Client(url) as b:
            ns = await a.get_namespace_index("urn:ladderc:plc")

            class Side:
                def __init__(self, client):
                    self.node = lambda n: client.get_node(f"ns={ns};s=D{n}")

                async def write(self, register, value):
                    variant = ua.Variant(signed(value), ua.VariantType.Int16)
                    await self.node(register).write_value(ua.DataValue(variant))

                async def read(self, register):
                    return (await self.node(register).read_value()) & 0xFFFF

            first, second = Side(a), Side(b)
            misses = 0
            began = time.time()
            for i in range(pairs):
                value = (i * 7919 + 1) % 30000
                await first.write(100, value)
                if await first.read(100) != value:
                    misses += 1
            pair_seconds = time.time() - began
            lost = 0
            rounds = (rmws + 15) // 16
            began = time.time()
            await first.write(300, 0)
            for _ in range(rounds):
                for bit in range(16):
                    side = first if bit % 2 == 0 else second
                    await side.write(300, (await side.read(300)) | (1 << bit))
                lost += 16 - bin(await first.read(300)).count("1")
                await first.write(300, 0)
            return misses, lost, pair_seconds, time.time() - began, rounds * 16

    return asyncio.run(main())


if protocol in ("modbus", "rtu"):
    result = run(*modbus_clients())
elif protocol == "melsec":
    result = run(*melsec_clients())
elif protocol == "http":
    result = run(*http_clients())
elif protocol == "opcua":
    result = run_opcua()
else:
    raise SystemExit("unknown protocol " + protocol)

misses, lost, pair_seconds, rmw_seconds, done = result
print(json.dumps({
    "misses": misses,
    "lost": lost,
    "pairs": pairs,
    "rmws": done,
    "pairs_per_s": round(pairs / max(pair_seconds, 1e-9), 1),
    "rmws_per_s": round(done / max(rmw_seconds, 1e-9), 1),
}))
