#!/usr/bin/env bash
# Set everything up (see scripts/setup.sh, with the test extras) and run the test
# suite (with the doctests of the modules listed in pyproject.toml) and the linter,
# then build the documentation with warnings as errors (scripts/docs.sh).
# Extra arguments go to pytest (e.g. -m "not gl"); with them, the docs are not built
# (the gallery needs GL, and a subset of the tests is not a full check).
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/setup.sh" test
ruff check morphkit tests samples docs
python -m pytest -q "$@"
if [ "$#" -eq 0 ]; then
  # the rendering tests again on Mesa's EGL (software; the platform a GPU uses): MORPHKIT_GL=egl
  MORPHKIT_GL=egl python -m pytest -q -p no:cacheprovider tests/test_render.py
  bash "$MORPHKIT_ROOT/scripts/docs.sh"
fi
