#!/bin/sh
# The closed-loop scenes' accuracy against the tolerance (docs/accuracy.md, "Closed loops"):
# each passive linkage of models/linkages/ run by `mbstream simulate` with each method able
# to hold its loops (bdf: Baumgarte and projection; adams: Baumgarte alone; ida: the GGL
# index-2 DAE) at rtol 1e-6, 1e-8, 1e-10 (atol = rtol / 100), one CSV row a run from its
# stats.json: status, steps, CPU ms, relative energy error, largest position and velocity
# constraint residual over the frames.
#
#   bench/loop_accuracy.sh [BUILD_DIR] > loop_accuracy.csv
set -eu
build=${1:-build}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
echo "scene,method,rtol,status,steps,cpu_ms,energy_error,position_residual_m,velocity_residual"
for scene in four_bar slider_crank delta; do
  for method in bdf adams ida; do
    for rtol in 1e-6 1e-8 1e-10; do
      atol=$(/usr/bin/python3 -c "print($rtol / 100)")
      rm -rf "$out/run"
      "$build/client/mbstream" simulate "models/linkages/$scene.sdf" \
        --spec "models/linkages/$scene-passive.json" --formulation joint --method "$method" \
        --rtol "$rtol" --atol "$atol" --out "$out/run" >/dev/null 2>&1 || true
      /usr/bin/python3 - "$out/run/stats.json" "$scene" "$method" "$rtol" <<'PY'
import json, sys
path, scene, method, rtol = sys.argv[1:]
try:
    s = json.load(open(path))
except OSError:
    print(f"{scene},{method},{rtol},NO RESULT,,,,,")
    sys.exit()
a, loops = s.get("accuracy") or {}, s.get("loops") or {}
def g(v):
    return "" if v is None else f"{v:.2g}"
status = s["status"] if s["status"] == "FINISHED" else f"{s['status']} at t = {s['t_reached']:.3g} s"
print(f"{scene},{method},{rtol},{status},{s['steps']},{s['cpu_s'] * 1e3:.1f},"
      f"{g(a.get('energy_error_max_rel'))},{g(loops.get('position_residual_max_m'))},"
      f"{g(loops.get('velocity_residual_max'))}")
PY
    done
  done
done
