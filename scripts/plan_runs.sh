#!/bin/bash
# The 12 plan runs of docs/results/planning.md ("Planning a scene to an error budget"): the three
# example scenes (each without and with a shadow budget) and six unseen scenes written by
# `morphkit billboards ... --save-scene`, each planned with --sweep; one row of the table a run.
# Usage: bash scripts/plan_runs.sh OUT   (about 10 minutes with warm tables; ring-fly's 12 ring
# tables take about 33 minutes to measure cold)
set -euo pipefail
out=${1:?usage: bash scripts/plan_runs.sh OUT}
cd "$(dirname "$0")/.."
M=".venv/bin/python -m morphkit"
mkdir -p "$out"
scene() { name=$1; shift; $M billboards "$@" --save-scene "$out/$name.json" > /dev/null; }
scene orbit-sun --asset chair --asset person --n 60 --path orbit --sun-path day
scene orbit-soft --asset chair --asset person --n 60 --path orbit --sun-path day --shadows --soft 4
scene ring-fly --asset cow --asset teapot --asset tree --n 200 --path fly
scene fly-day --asset cow --asset teapot --asset tree --n 200 --path fly --shadows --sun-path day
scene orbit-crate --asset morphkit/data/photo_crate.glb --asset cow --asset chair --n 100 --path orbit --sun-path day
scene fly-shadows --asset person --asset teapot --asset tree --n 150 --path flyover --shadows
plan() { name=$1; shift; scene=$1; shift
  $M plan "$scene" "$@" --sweep -o "$out/$name" --overwrite > "$out/$name.log" 2>&1 || echo "$name failed: $out/$name.log"
  tail -n 2 "$out/$name.log" | head -n 1; }
P="--budget billboard-psnr=20 --budget billboard-iou=0.8"
plan flyover samples/scenes/flyover.json $P
plan flyover-shadow samples/scenes/flyover.json $P --budget shadow-iou=0.9
plan village samples/scenes/village.glb --budget billboard-psnr=25 --budget billboard-iou=0.9
plan village-shadow samples/scenes/village.glb --budget billboard-psnr=25 --budget billboard-iou=0.9 --budget shadow-iou=0.9
plan forest samples/scenes/forest.json --budget billboard-psnr=17 --budget billboard-iou=0.75
plan forest-shadow samples/scenes/forest.json --budget billboard-psnr=17 --budget billboard-iou=0.75 --budget shadow-iou=0.9
plan orbit-sun "$out/orbit-sun.json" $P
plan orbit-soft "$out/orbit-soft.json" $P --budget shadow-iou=0.85
plan fly-day "$out/fly-day.json" --budget billboard-psnr=18 --budget billboard-iou=0.75 --budget shadow-iou=0.85
plan ring-fly "$out/ring-fly.json" --budget billboard-psnr=14 --budget billboard-iou=0.7
plan orbit-crate "$out/orbit-crate.json" $P
plan fly-shadows "$out/fly-shadows.json" --budget billboard-psnr=18 --budget billboard-iou=0.75 --budget shadow-iou=0.85
