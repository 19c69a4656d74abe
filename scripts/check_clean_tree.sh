#!/usr/bin/env bash
# Tests never write into the source tree. Run around a ctest run:
#   scripts/check_clean_tree.sh snapshot FILE   records the checkout's untracked and modified
#                                               files (and their contents' hashes) in FILE
#   scripts/check_clean_tree.sh compare FILE    fails, naming them, when files were added,
#                                               changed or removed since the snapshot
# Build directories and the other ignored paths (.gitignore) do not count. Files that were
# already modified before the snapshot (a contributor's own edits) count only if a test
# changed them again.
set -euo pipefail
cd "$(dirname "$0")/.."

state() {  # one line per untracked or modified path: "<status> <path> <hash or ->"
  git status --porcelain=v1 --untracked-files=all -z | tr '\0' '\n' | while IFS= read -r line; do
    [ -n "$line" ] || continue
    path=${line:3}
    if [ -f "$path" ]; then
      printf '%s %s\n' "$line" "$(git hash-object --no-filters -- "$path")"
    else
      printf '%s -\n' "$line"
    fi
  done | LC_ALL=C sort
}

case "${1:-}" in
  snapshot) state >"$2" ;;
  compare)
    now=$(mktemp)
    trap 'rm -f "$now"' EXIT
    state >"$now"
    if ! cmp -s "$2" "$now"; then
      echo "check_clean_tree: the tests left files in the source tree (tests must write to a" \
        "temporary directory); git status lines that differ from before the tests:" >&2
      diff "$2" "$now" | sed -n 's/^[<>] /  /p' >&2
      exit 1
    fi
    echo "check_clean_tree: the source tree is as it was before the tests"
    ;;
  *) echo "usage: scripts/check_clean_tree.sh snapshot|compare FILE" >&2; exit 2 ;;
esac
