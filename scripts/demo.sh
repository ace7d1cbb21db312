#!/usr/bin/env bash
# Set everything up (see scripts/setup.sh) and run the main job: the demo scenes.
# Usage: bash scripts/demo.sh [OUT_DIR]   (default: morphkit-demo)
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/setup.sh" ""
out="${1:-morphkit-demo}"
morphkit demo -o "$out"
