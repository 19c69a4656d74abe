#!/usr/bin/python3
"""Runs one command against a fresh mbstream-server (the ctest harness of the Python client).

    run_with_server.py --server-binary PATH [--viewer-binary PATH] [--pythonpath DIRS]
                       [--server-arg ARG]... -- CMD...

Starts PATH --listen 127.0.0.1:0 --data <a temporary folder>, waits for its
`listening on ADDR` line, runs CMD with MBSTREAM_SERVER=ADDR (and `--server ADDR`
appended when CMD is an example script), then stops the server with SIGINT (at once, without
draining) and removes the folder. With --viewer-binary, an offscreen viewer
(scripts/with-xvfb.sh) follows the server's runs while CMD runs. Exits with CMD's exit code, or 1 when the server fails to start or does not stop
cleanly.
"""
import argparse
import os
import signal
import subprocess
import sys
import tempfile
import threading
import time

# A private Xvfb per viewer, its display number picked by Xvfb itself (race-free).
WITH_XVFB = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..",
                         "scripts", "with-xvfb.sh")

START_TIMEOUT_S = 30
STOP_TIMEOUT_S = 20


def start_server(binary, data_dir, extra_args):
    command = [binary, "--listen", "127.0.0.1:0", "--data", data_dir] + extra_args
    server = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=None, text=True)
    address = []
    found = threading.Event()

    def read_stdout():
        # Keeps draining stdout after the address so the server never blocks on a full pipe;
        # its log lines go to stderr (ctest shows them with --output-on-failure).
        for line in server.stdout:
            if not found.is_set() and line.startswith("listening on "):
                address.append(line.split("listening on ", 1)[1].strip())
                found.set()
            sys.stderr.write("server: " + line)
        found.set()

    threading.Thread(target=read_stdout, daemon=True).start()
    found.wait(START_TIMEOUT_S)
    if not address:
        server.kill()
        server.wait()
        sys.exit("run_with_server: %s did not print 'listening on ADDR' within %d s (exit %s)"
                 % (binary, START_TIMEOUT_S, server.poll()))
    return server, address[0]


def start_viewer(binary, address):
    command = [WITH_XVFB, binary, "--server", address, "--follow", "--offscreen",
               "--size", "320x240", "--no-hud"]
    # Its own process group: SIGTERM then reaches the viewer, not only with-xvfb.sh.
    viewer = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                              text=True, start_new_session=True)
    subscribed = threading.Event()

    def read_stdout():
        for line in viewer.stdout:
            if "subscribed to" in line:
                subscribed.set()
            sys.stderr.write("viewer: " + line)
        subscribed.set()

    threading.Thread(target=read_stdout, daemon=True).start()
    if not subscribed.wait(START_TIMEOUT_S) or viewer.poll() is not None:
        viewer.kill()
        sys.exit("run_with_server: the viewer did not subscribe within %d s" % START_TIMEOUT_S)
    return viewer


def stop_viewer(viewer):
    """SIGTERM to the viewer's process group (with-xvfb.sh, Xvfb and the viewer)."""
    try:
        os.killpg(viewer.pid, signal.SIGTERM)
        viewer.wait(STOP_TIMEOUT_S)
    except (ProcessLookupError, subprocess.TimeoutExpired):
        try:
            os.killpg(viewer.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
        viewer.wait()


def stop_server(server):
    # SIGINT stops at once (runs INTERRUPTED); SIGTERM would drain, giving runs --grace-s.
    server.send_signal(signal.SIGINT)
    try:
        return server.wait(STOP_TIMEOUT_S)
    except subprocess.TimeoutExpired:
        server.kill()
        server.wait()
        print("run_with_server: the server did not stop within %d s of SIGINT" % STOP_TIMEOUT_S,
              file=sys.stderr)
        return -1


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--server-binary", required=True)
    parser.add_argument("--viewer-binary", help="also run an offscreen viewer following runs")
    parser.add_argument("--pythonpath", default="", help="prepended to PYTHONPATH (':'-separated)")
    parser.add_argument("--server-arg", action="append", default=[],
                        help="an extra argument for the server (repeatable)")
    parser.add_argument("command", nargs=argparse.REMAINDER)
    args = parser.parse_args()
    command = args.command[1:] if args.command[:1] == ["--"] else args.command
    if not command:
        parser.error("no command given after --")

    with tempfile.TemporaryDirectory(prefix="mbstream-py-") as tmp:
        server, address = start_server(args.server_binary, os.path.join(tmp, "data"),
                                       args.server_arg)
        viewer = start_viewer(args.viewer_binary, address) if args.viewer_binary else None
        env = dict(os.environ, MBSTREAM_SERVER=address)
        if args.pythonpath:
            env["PYTHONPATH"] = os.pathsep.join(
                p for p in [args.pythonpath, env.get("PYTHONPATH", "")] if p)
        if any(os.path.basename(os.path.dirname(c)) == "examples" and c.endswith(".py")
               for c in command[:2]):
            command = command + ["--server", address]
        began = time.monotonic()
        try:
            code = subprocess.call(command, env=env)
        finally:
            if viewer:
                stop_viewer(viewer)
            stopped = stop_server(server)
        print("run_with_server: command exited %d after %.1f s; server exited %d"
              % (code, time.monotonic() - began, stopped), file=sys.stderr)
        if code == 0 and stopped != 0:
            return 1
        return code


if __name__ == "__main__":
    sys.exit(main())
