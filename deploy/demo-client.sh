#!/usr/bin/env bash
# The client's part of the demo, run as is by the compose `client` service and by the
# multi-host test: submit a model, run an experiment on it, download the results.
#
#   demo-client.sh MODEL_DIR SPEC.json OUT_DIR
#
# The server, CA and token come from MBSTREAM_SERVER, MBSTREAM_CA and MBSTREAM_TOKEN_FILE
# (read by the CLI itself); MBSTREAM_REALTIME (default 1) paces the run (4 = four times
# faster than real time); MBSTREAM_CLI names the CLI binary (default `mbstream` on PATH).
# Prints the run id on stdout; exit 0 only when the run finished.
set -euo pipefail

if [ $# -ne 3 ]; then
  echo "usage: demo-client.sh MODEL_DIR SPEC.json OUT_DIR" >&2
  exit 2
fi
model_dir=$1 spec=$2 out=$3
cli=${MBSTREAM_CLI:-mbstream}
realtime=${MBSTREAM_REALTIME:-1}

model=$("$cli" submit "$model_dir")
echo "demo-client: submitted $model_dir as model $model" >&2
"$cli" run "$model" --spec "$spec" --realtime "$realtime" --out "$out"
