#!/bin/bash
# The levels-of-detail runs of docs/results/planning.md ("Levels of detail from a plan"): the flyover
# planned, each of its assets and the scene exported with the plan, every file validated.
# Usage: bash scripts/lod_export_runs.sh OUT   (after scripts/setup.sh test: the validator)
set -euo pipefail
out=${1:?usage: bash scripts/lod_export_runs.sh OUT}
cd "$(dirname "$0")/.."
M=".venv/bin/python -m morphkit"
mkdir -p "$out"
$M plan samples/scenes/flyover.json --budget billboard-psnr=20 --budget billboard-iou=0.8 \
  --budget shadow-iou=0.9 -o "$out/plan" --overwrite
for a in tree person chair; do $M export $a -o "$out/$a.glb" --plan "$out/plan" --overwrite; done
$M export morphkit/data/photo_crate.glb -o "$out/crate.glb" --plan "$out/plan" --plan-asset crate --overwrite
$M export samples/scenes/flyover.json -o "$out/flyover.glb" --plan "$out/plan" --overwrite
$M export samples/scenes/flyover.json -o "$out/flyover_plain.glb" --overwrite
for f in tree person chair crate flyover flyover_plain; do
  echo -n "$f: "
  NODE_PATH=.cache/node/node_modules node scripts/gltf_validate.js "$out/$f.glb" | python3 -c \
    "import json, sys; r = json.load(sys.stdin); print(r['errors'], 'errors', r['warnings'], 'warnings')"
done
