#!/usr/bin/env bash
# Set everything up (see scripts/setup.sh, with the test extras) and run the test
# suite and the linter. Extra arguments go to pytest (e.g. -m "not gl").
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/setup.sh" test
ruff check morphkit tests samples
python -m pytest -q "$@"
