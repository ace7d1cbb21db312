#!/usr/bin/env bash
# The benches whose trade-off a GPU changes, run on EGL (issue #29: "GPU rows in the benches";
# issue #26: the sun change and the whole frame against the direct render), each into its own
# JSON in OUT. Every row's "gl" names the platform and the renderer string, so a run on a
# software EGL says so. Usage (morphkit importable; MORPHKIT_GL defaults to egl here):
#
#   bash scripts/gpu_bench.sh OUT [PART ...]
#
# PARTs (default: info render shadows scene soft):
#   info     the GL platform, renderer and version, CPU count, python and library versions
#   render   bench render --sections depth,accuracy (light-view depth maps by mesh size and map side)
#   shadows  bench shadows --sections complexity,frame,frame-once (direct re-render against the
#            warps by mesh size; whole frames with the camera drawn once)
#   scene    bench scene --sections sun-change (the field's sun change against rendering every
#            mesh from the sun, 100 and 1000 instances at ~6k and >= 50k faces)
#   soft     bench soft (area-light soft shadows, N maps re-rendered against warped)
#   bake     bench bake on a library of $ASSETS (default 256) assets, $WORKERS (default
#            "1 4 8 16") local workers, one repeat, the serial loop timed once, no phase with
#            Dask's default worker settings
set -uo pipefail
out=${1:?usage: bash scripts/gpu_bench.sh OUT [PART ...]}
shift
mkdir -p "$out"
export MORPHKIT_GL="${MORPHKIT_GL:-egl}"
py="${PYTHON:-python3}"
parts=("$@")
[ "${#parts[@]}" -gt 0 ] || parts=(info render shadows scene soft)
status=0
for part in "${parts[@]}"; do
  echo "== gpu_bench: $part ($(date -u +%H:%M:%S))"
  case "$part" in
    info)
      "$py" - <<'EOF' || status=1
import json, os, platform, sys
import cv2, numpy, trimesh
from morphkit.render import gl_info
print(json.dumps({"gl": gl_info(), "cpus": os.cpu_count(), "python": sys.version.split()[0],
                  "machine": platform.machine(), "numpy": numpy.__version__, "cv2": cv2.__version__,
                  "trimesh": trimesh.__version__}, indent=1))
EOF
      ;;
    render) "$py" -m morphkit bench render --sections depth,accuracy --json "$out/render.json" || status=1 ;;
    shadows) "$py" -m morphkit bench shadows --sections complexity,frame,frame-once \
               --json "$out/shadows.json" || status=1 ;;
    scene) "$py" -m morphkit bench scene --sections sun-change --json "$out/scene.json" || status=1 ;;
    soft) "$py" -m morphkit bench soft --json "$out/soft.json" || status=1 ;;
    bake)
      # -c, not a here-document: Dask's worker processes re-import the parent's main module by path
      ASSETS="${ASSETS:-256}" WORKERS="${WORKERS:-1 4 8 16}" OUTJSON="$out/bake.json" "$py" -c '
import os
from morphkit.bench import run_suite
run_suite("bake", json_path=os.environ["OUTJSON"],
          options={"workers": [int(w) for w in os.environ["WORKERS"].split()],
                   "assets": int(os.environ["ASSETS"]), "repeats": 1, "serial_once": True,
                   "dask_defaults": False})' || status=1
      ;;
    *) echo "gpu_bench: unknown part $part (info render shadows scene soft bake)" >&2; exit 2 ;;
  esac
done
exit $status
