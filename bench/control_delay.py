#!/usr/bin/python3
"""A controller across a delayed link: the control period against the run's rate (issue 45).

    /usr/bin/python3 bench/control_delay.py --build build [--delay-ms 1] [--periods 1e-3,...]

Starts mbstream-server on loopback, a TCP relay in front of it that holds every chunk of
bytes for --delay-ms in each direction (a link with that one-way delay and no bandwidth
limit; the kernel's netem qdisc, which a network namespace would use, is not available on
these machines), and runs client/examples/control_pd (a 6-joint PD on the IRB 1600) through
the relay at each period, 10 s of simulated time, then once more straight to the server (no
delay) at each period. Prints one line per run: the period, the link, the wall time and the
rate (simulated s per wall s). Each control step is one round trip, so across a link of one-way
delay d a run of duration T at period h takes at least (T / h) 2 d: the rate is at most
h / (2 d).
"""

import argparse
import asyncio
import os
import re
import subprocess
import sys
import tempfile
import threading


def start_server(build, data):
    server = subprocess.Popen(
        [os.path.join(build, "server/app/mbstream-server"), "--listen", "127.0.0.1:0", "--data", data],
        stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    for line in server.stdout:  # until it says where it listens
        match = re.search(r"listening on (\S+)", line)
        if match:
            threading.Thread(target=lambda: [None for _ in server.stdout], daemon=True).start()
            return server, match.group(1)
    raise RuntimeError("mbstream-server did not start")


async def relay(reader, writer, delay):
    """Copies reader to writer, each chunk after `delay` s, in order."""
    queue = asyncio.Queue()

    async def receive():
        loop = asyncio.get_running_loop()
        while True:
            data = await reader.read(65536)
            await queue.put((loop.time() + delay, data))
            if not data:
                return

    async def send():
        loop = asyncio.get_running_loop()
        while True:
            due, data = await queue.get()
            wait = due - loop.time()
            if wait > 0:
                await asyncio.sleep(wait)
            if not data:
                writer.close()
                return
            writer.write(data)
            await writer.drain()

    await asyncio.gather(receive(), send())


def start_relay(target, delay):
    """A delaying TCP relay to `target` on a thread of its own; returns its address."""
    host, port = target.rsplit(":", 1)
    ready = threading.Event()
    address = []

    async def main():
        async def connection(client_reader, client_writer):
            server_reader, server_writer = await asyncio.open_connection(host, int(port))
            await asyncio.gather(relay(client_reader, server_writer, delay),
                                 relay(server_reader, client_writer, delay),
                                 return_exceptions=True)

        listener = await asyncio.start_server(connection, "127.0.0.1", 0)
        address.append("127.0.0.1:%d" % listener.sockets[0].getsockname()[1])
        ready.set()
        async with listener:
            await listener.serve_forever()

    threading.Thread(target=lambda: asyncio.run(main()), daemon=True).start()
    ready.wait()
    return address[0]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--build", default="build")
    parser.add_argument("--delay-ms", type=float, default=1.0)
    # Longer periods need smaller gains: the example's wrist PD (kd h / inertia) goes unstable
    # beyond 2 ms.
    parser.add_argument("--periods", default="5e-4,1e-3,2e-3")
    parser.add_argument("--duration", type=float, default=10.0)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as data:
        server, address = start_server(args.build, data)
        try:
            delayed = start_relay(address, args.delay_ms / 1000.0)
            for link, target in (("%g ms each way" % args.delay_ms, delayed), ("loopback", address)):
                for period in args.periods.split(","):
                    out = subprocess.run(
                        [os.path.join(args.build, "client/control_pd"), target, period,
                         str(args.duration)], capture_output=True, text=True, check=False)
                    match = re.search(r"in ([0-9.]+) s of wall time, ([0-9.]+) x real time", out.stdout)
                    if out.returncode != 0 or not match:
                        print("period %s s, %s: FAILED\n%s%s" % (period, link, out.stdout, out.stderr))
                        return 1
                    bound = float(period) / (2 * args.delay_ms / 1000.0) if link != "loopback" else None
                    print("period %-6s s  %-16s wall %7.2f s  %6.2f x real time%s" % (
                        period, link, float(match.group(1)), float(match.group(2)),
                        "  (bound h / 2d = %.2f x)" % bound if bound else ""))
                    sys.stdout.flush()
        finally:
            server.terminate()
            server.wait()
    return 0


if __name__ == "__main__":
    sys.exit(main())
