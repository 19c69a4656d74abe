#!/usr/bin/env bash
# Prints, one per line, the Debian packages that hold the shared libraries the given
# binaries load (ldd, then dpkg -S). The Dockerfile's build stage runs it so that each slim
# runtime stage installs exactly the libraries its binaries need, whatever the build found.
#
#   runtime-packages.sh BINARY...
set -euo pipefail
[ $# -gt 0 ] || { echo "usage: runtime-packages.sh BINARY..." >&2; exit 2; }
for binary in "$@"; do
  ldd "$binary" | awk '/=> \//{ print $3 }'
done | sort -u | while read -r lib; do
  # bookworm merges /lib into /usr/lib: dpkg knows one of the two spellings.
  dpkg -S "$lib" 2>/dev/null || dpkg -S "$(realpath "$lib")" 2>/dev/null ||
    dpkg -S "/usr$lib" 2>/dev/null || { echo "runtime-packages: no package holds $lib" >&2; exit 1; }
done | cut -d: -f1 | sort -u
