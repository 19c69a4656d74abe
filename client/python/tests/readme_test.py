#!/usr/bin/env python3
"""Runs the Python code of client/python/README.md (the quick start, the error example and
the notebook), in order and in one namespace, against $MBSTREAM_SERVER, so that the README
stays true. ctest runs it through run_with_server.py with the venv's python, from the
repository root."""
import os
import re
import sys

import matplotlib

matplotlib.use("Agg")

README = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "README.md")


def main():
    address = os.environ["MBSTREAM_SERVER"]
    with open(README, encoding="utf-8") as f:
        blocks = re.findall(r"```python\n(.*?)```", f.read(), re.DOTALL)
    if len(blocks) < 5:
        sys.exit("readme_test: expected the quick start, the error example and three notebook "
                 "cells, found %d python blocks" % len(blocks))
    namespace = {"__name__": "__readme__"}
    for number, code in enumerate(blocks, 1):
        print("--- README python block %d" % number, flush=True)
        exec(compile(code.replace("127.0.0.1:50051", address), "README block %d" % number,
                     "exec"), namespace)
    print("readme_test: %d blocks ran" % len(blocks))
    return 0


if __name__ == "__main__":
    sys.exit(main())
