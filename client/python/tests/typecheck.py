#!/usr/bin/python3
"""Type-checks the installed mbstream_client with mypy (Debian's python3-mypy), so that the
hints of the public API stay true. Exits 77 (ctest: skipped) when mypy is not installed."""
import os
import subprocess
import sys

try:
    import mypy  # noqa: F401
except ImportError:
    print("typecheck: mypy is not installed (apt-get install python3-mypy): skipped")
    sys.exit(77)

config = os.path.join(os.path.dirname(os.path.abspath(__file__)), "mypy.ini")
# From another folder, so that mypy finds the installed package, not the source tree.
sys.exit(subprocess.call([sys.executable, "-m", "mypy", "--config-file", config,
                          "--cache-dir", os.devnull,  # no .mypy_cache left behind
                          "-p", "mbstream_client"], cwd="/"))
