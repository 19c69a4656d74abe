#!/usr/bin/env bash
# Prints, one per line, the Debian packages that hold the shared libraries the given
# binaries load (ldd, then dpkg -S). deploy/stage.sh and deploy/cluster/stage.sh run it so
# that each slim runtime image installs exactly the libraries its binaries need, whatever
# the build found.
#
#   runtime-packages.sh BINARY...
set -euo pipefail
[ $# -gt 0 ] || { echo "usage: runtime-packages.sh BINARY..." >&2; exit 2; }
mapfile -t libs < <(for binary in "$@"; do ldd "$binary" | awk '/=> \//{ print $3 }'; done | sort -u)
[ ${#libs[@]} -gt 0 ] || exit 0
# bookworm merges /lib into /usr/lib: dpkg knows one of the spellings of each library (as
# ldd found it, its real path, or under /usr). One dpkg query for all of them: one per
# library took minutes on a loaded machine.
spellings=()
for lib in "${libs[@]}"; do spellings+=("$lib" "$(realpath "$lib")" "/usr$lib"); done
owners=$(dpkg -S "${spellings[@]}" 2>/dev/null || true)
for lib in "${libs[@]}"; do
  package=""
  for spelling in "$lib" "$(realpath "$lib")" "/usr$lib"; do
    package=$(awk -v path="$spelling" '{ p = $0; sub(/^[^:]*(:[^:]*)?: /, "", p) } p == path { sub(/:.*/, ""); print; exit }' <<<"$owners")
    [ -n "$package" ] && break
  done
  [ -n "$package" ] || { echo "runtime-packages: no package holds $lib" >&2; exit 1; }
  echo "$package"
done | sort -u
