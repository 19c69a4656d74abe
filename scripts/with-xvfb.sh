#!/usr/bin/env bash
# with-xvfb.sh COMMAND [ARGS...]: runs COMMAND with DISPLAY set to a private Xvfb, stops the
# Xvfb afterwards and exits with COMMAND's status. Xvfb picks its own free display number
# (-displayfd), so two calls started at the same moment never collide; `xvfb-run -a` looks for
# a free number before starting Xvfb, and two of them started together (ctest -j2 running two
# viewer tests) may pick the same one, and one fails with "Xvfb failed to start".
#
# SIGTERM and SIGINT are passed on to COMMAND. XVFB_SCREEN sets the screen (default
# 1280x1024x24). Needs Xvfb (Debian package xvfb; scripts/setup.sh installs it).
set -uo pipefail

if [ $# -eq 0 ]; then
  echo "usage: with-xvfb.sh COMMAND [ARGS...]" >&2
  exit 2
fi
command -v Xvfb >/dev/null || {
  echo "with-xvfb.sh: Xvfb is not installed (Debian package xvfb)" >&2
  exit 127
}

# Xvfb writes the display number to its stdout (the coprocess pipe) once it accepts clients.
coproc XVFB { exec Xvfb -displayfd 1 -screen 0 "${XVFB_SCREEN:-1280x1024x24}" -nolisten tcp \
  -noreset 2>/dev/null; }
xvfb_pid=$XVFB_PID
stop_xvfb() {
  kill "$xvfb_pid" 2>/dev/null
  wait "$xvfb_pid" 2>/dev/null
}
trap stop_xvfb EXIT
display=
read -r -t 60 -u "${XVFB[0]}" display
if ! [[ "$display" =~ ^[0-9]+$ ]]; then
  echo "with-xvfb.sh: Xvfb did not start (no display number within 60 s)" >&2
  exit 1
fi

DISPLAY=":$display" "$@" &
child=$!
forward() { kill -"$1" "$child" 2>/dev/null; }
trap 'forward TERM' TERM
trap 'forward INT' INT
# `wait` returns early (status > 128) when a trapped signal arrives: wait again until the
# command itself has ended.
while true; do
  wait "$child"
  status=$?
  kill -0 "$child" 2>/dev/null || break
done
exit "$status"
