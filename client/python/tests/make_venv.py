#!/usr/bin/python3
"""Installs mbstream_client into a fresh virtual environment, as a user would (the ctest
fixture of the Python tests: they then run with that environment's python, never the source).

    make_venv.py --source client/python --venv DIR [--editable]

Copies the source folder (without build products) to DIR.src, makes DIR with
`python3 -m venv --system-site-packages --without-pip` (Debian's grpcio, protobuf, numpy,
matplotlib come from the system), runs `python3 -m pip --python DIR/bin/python install
--no-build-isolation --no-deps [-e] DIR.src` (no network: Debian's setuptools builds it,
setup.py generates the stubs from the checkout's proto/), and checks that `import
mbstream_client` in DIR finds the installed copy, with its stubs, py.typed and the version of
the top-level CMakeLists.txt. Prints the install time.
"""
import argparse
import os
import re
import shutil
import subprocess
import sys
import time

CHECK = r"""
import importlib.resources, os, sys
import mbstream_client as mb
expected_dir, version = sys.argv[1], sys.argv[2]
here = os.path.realpath(os.path.dirname(mb.__file__))
assert here.startswith(os.path.realpath(expected_dir)), "imported %s, not from %s" % (
    here, expected_dir)
assert mb.__version__ == version, (mb.__version__, version)
assert os.path.isfile(os.path.join(here, "py.typed")), "py.typed is missing"
assert mb.simulation_service_pb2_grpc.SimulationStub
assert "mbstream" not in sys.modules, "a top-level mbstream package was imported"
print("mbstream_client %s from %s" % (mb.__version__, here))
"""


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--source", required=True, help="the client/python folder")
    parser.add_argument("--venv", required=True, help="the environment to (re)create")
    parser.add_argument("--editable", action="store_true", help="pip install -e")
    args = parser.parse_args()
    source = os.path.abspath(args.source)
    repo = os.path.normpath(os.path.join(source, "..", ".."))
    venv = os.path.abspath(args.venv)
    copy = venv + ".src"
    with open(os.path.join(repo, "CMakeLists.txt"), encoding="utf-8") as f:
        version = re.search(r"project\(\s*mbstream\s+VERSION\s+([0-9.]+)", f.read()).group(1)

    began = time.monotonic()
    for path in (venv, copy):
        shutil.rmtree(path, ignore_errors=True)
    shutil.copytree(source, copy, ignore=shutil.ignore_patterns(
        "build", "*.egg-info", "__pycache__", "*_pb2.py", "*_pb2_grpc.py", "_version.py"))
    subprocess.run([sys.executable, "-m", "venv", "--system-site-packages", "--without-pip",
                    venv], check=True)
    python = os.path.join(venv, "bin", "python")
    env = dict(os.environ, MBSTREAM_SOURCE_DIR=repo, PIP_NO_INDEX="1",
               PIP_DISABLE_PIP_VERSION_CHECK="1")
    env.pop("PYTHONPATH", None)
    command = [sys.executable, "-m", "pip", "--python", python, "install", "--quiet",
               "--no-build-isolation", "--no-deps"] + (["-e"] if args.editable else []) + [copy]
    subprocess.run(command, check=True, env=env)
    installed = time.monotonic() - began
    # From another folder, so that nothing but the installed copy can be imported.
    expected = copy if args.editable else venv
    subprocess.run([python, "-c", CHECK, expected, version], check=True, env=env, cwd="/")
    print("make_venv: %s install into %s took %.1f s"
          % ("editable" if args.editable else "wheel", venv, installed))
    return 0


if __name__ == "__main__":
    sys.exit(main())
