"""Build steps of the mbstream_client package that pyproject.toml cannot declare.

1. The version is the project's: `project(mbstream VERSION X.Y.Z)` in the repository's top-level
   CMakeLists.txt (the single source of truth), written to mbstream_client/_version.py.
2. The gRPC stubs are generated from proto/mbstream/v1/*.proto at build time and placed inside
   the package (mbstream_client/<name>_pb2.py, <name>_pb2_grpc.py), their imports rewritten
   from `from mbstream.v1 import x_pb2` to `from . import x_pb2`: one installed package, no
   top-level `mbstream` that could collide with anything.

The compiler is, in order: $PROTOC (or `protoc` on PATH) with $GRPC_PYTHON_PLUGIN (or
`grpc_python_plugin` on PATH) -- Debian's protobuf-compiler and protobuf-compiler-grpc, the
same protoc the C++ build uses; else grpcio-tools (`python3 -m grpc_tools.protoc`). Debian
bookworm's python3-grpc-tools (1.14) bundles a protoc too old for proto3 `optional` fields, so
on Debian the first is the one that works.

The repository root (for proto/ and CMakeLists.txt) is $MBSTREAM_SOURCE_DIR, else the folder
two levels above this file (client/python -> the checkout).

Install (Debian's python3-setuptools, no network):
    pip install --no-build-isolation --no-deps ./client/python       # or -e for editable
"""
import os
import re
import shutil
import subprocess
import sys
import tempfile

from setuptools import setup
from setuptools.command.build_py import build_py

HERE = os.path.dirname(os.path.abspath(__file__))
PACKAGE = "mbstream_client"


def source_root():
    root = os.environ.get("MBSTREAM_SOURCE_DIR") or os.path.join(HERE, "..", "..")
    root = os.path.normpath(os.path.abspath(root))
    if not os.path.isfile(os.path.join(root, "proto", "mbstream", "v1",
                                       "simulation_service.proto")):
        sys.exit("mbstream_client: no proto/mbstream/v1/simulation_service.proto under %s; "
                 "install from a checkout of mbstream (pip install ./client/python) or set "
                 "MBSTREAM_SOURCE_DIR to the checkout" % root)
    return root


def project_version(root):
    """X.Y.Z from `project(mbstream VERSION X.Y.Z ...)` in the top-level CMakeLists.txt."""
    with open(os.path.join(root, "CMakeLists.txt"), encoding="utf-8") as f:
        match = re.search(r"project\(\s*mbstream\s+VERSION\s+([0-9]+(?:\.[0-9]+)*)", f.read())
    if not match:
        sys.exit("mbstream_client: no `project(mbstream VERSION X.Y.Z` in %s/CMakeLists.txt"
                 % root)
    return match.group(1)


def _compiler_command(proto_root, out):
    protoc = os.environ.get("PROTOC") or shutil.which("protoc")
    plugin = os.environ.get("GRPC_PYTHON_PLUGIN") or shutil.which("grpc_python_plugin")
    if protoc and plugin:
        return [protoc, "-I", proto_root, "--python_out=" + out, "--pyi_out=" + out,
                "--grpc_out=" + out, "--plugin=protoc-gen-grpc=" + plugin]
    try:
        import grpc_tools  # noqa: F401  (grpcio-tools)
    except ImportError:
        sys.exit("mbstream_client: generating the gRPC stubs needs protoc and grpc_python_plugin "
                 "(Debian: apt-get install protobuf-compiler protobuf-compiler-grpc) or "
                 "grpcio-tools; scripts/setup.sh installs the Debian packages")
    return [sys.executable, "-m", "grpc_tools.protoc", "-I", proto_root,
            "--python_out=" + out, "--grpc_python_out=" + out]


_IMPORT = re.compile(r"^from mbstream\.v1 import (\w+_pb2)", re.MULTILINE)
# The .pyi files (messages' type stubs, protoc --pyi_out) name the other modules' classes
# through `_run_spec_pb2.RunSpec`, imported as above.
_MODULE_NAME = re.compile(r"'mbstream\.v1\.(\w+_pb2)'")


def generate_stubs(root, package_dir):
    """Writes <name>_pb2.py and <name>_pb2_grpc.py for every proto/mbstream/v1/*.proto into
    package_dir, with imports relative to the package."""
    proto_root = os.path.join(root, "proto")
    v1 = os.path.join(proto_root, "mbstream", "v1")
    protos = sorted("mbstream/v1/" + n for n in os.listdir(v1) if n.endswith(".proto"))
    with tempfile.TemporaryDirectory(prefix="mbstream-stubs-") as out:
        command = _compiler_command(proto_root, out) + protos
        done = subprocess.run(command, cwd=proto_root, capture_output=True, text=True)
        if done.returncode != 0:
            sys.exit("mbstream_client: generating the stubs failed (%s):\n%s%s"
                     % (" ".join(command[:1]), done.stdout, done.stderr))
        generated = os.path.join(out, "mbstream", "v1")
        written = []
        for name in sorted(os.listdir(generated)):
            if not name.endswith((".py", ".pyi")):
                continue
            with open(os.path.join(generated, name), encoding="utf-8") as f:
                text = f.read()
            text = _IMPORT.sub(r"from . import \1", text)
            text = _MODULE_NAME.sub(r"'%s.\1'" % PACKAGE, text)
            target = os.path.join(package_dir, name)
            with open(target, "w", encoding="utf-8") as f:
                f.write("# Generated from proto/mbstream/v1 by setup.py at build time; "
                        "do not edit.\n# mypy: ignore-errors\n" + text)
            written.append(target)
    if not any(n.endswith("simulation_service_pb2_grpc.py") for n in written):
        sys.exit("mbstream_client: the compiler wrote no simulation_service_pb2_grpc.py")
    return written


def write_version(package_dir, version):
    path = os.path.join(package_dir, "_version.py")
    with open(path, "w", encoding="utf-8") as f:
        f.write('"""Written by setup.py from the top-level CMakeLists.txt; do not edit."""\n'
                "__version__ = %r\n" % version)
    return path


class BuildPyWithStubs(build_py):
    """build_py that also writes the stubs and _version.py: into the build folder for a
    wheel, into the source folder for an editable install (pip install -e)."""

    def run(self):
        super().run()
        root = source_root()
        if getattr(self, "editable_mode", False):
            package_dir = os.path.join(HERE, PACKAGE)
        else:
            package_dir = os.path.join(self.build_lib, PACKAGE)
        os.makedirs(package_dir, exist_ok=True)
        self._generated = generate_stubs(root, package_dir) + [
            write_version(package_dir, project_version(root))]

    def get_outputs(self, include_bytecode=True):
        return super().get_outputs(include_bytecode) + list(getattr(self, "_generated", []))


setup(version=project_version(source_root()), packages=[PACKAGE],
      package_data={PACKAGE: ["py.typed", "*.pyi"]}, cmdclass={"build_py": BuildPyWithStubs})
