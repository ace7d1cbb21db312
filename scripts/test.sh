#!/usr/bin/env bash
# Set everything up (see scripts/setup.sh, with the test extras) and run the test
# suite (with the doctests of the modules listed in pyproject.toml) and the linter,
# the GL-free tests once more under another OpenBLAS kernel (x86-64), then build the
# documentation with warnings as errors (scripts/docs.sh).
# Extra arguments go to pytest (e.g. -m "not gl"); with them, the docs are not built
# (the gallery needs GL, and a subset of the tests is not a full check).
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/setup.sh" test
ruff check morphkit tests samples docs
python -m pytest -q "$@"
if [ "$#" -eq 0 ]; then
  # the numeric core again under another OpenBLAS kernel: a result that flips with the last
  # bits of a matrix product is a bug in the geometry. Prescott (SSE3) runs on every x86-64
  # CPU (where the machine sets Prescott already, the first run was that kernel).
  if [ "$(uname -m)" = "x86_64" ] && [ "${OPENBLAS_CORETYPE:-}" != "Prescott" ]; then
    echo "morphkit tests: the tests without GL again under OPENBLAS_CORETYPE=Prescott"
    OPENBLAS_CORETYPE=Prescott python -m pytest -q -p no:cacheprovider -m "not gl"
  fi
  # the rendering tests again on Mesa's EGL (software; the platform a GPU uses): MORPHKIT_GL=egl
  MORPHKIT_GL=egl python -m pytest -q -p no:cacheprovider tests/test_render.py
  bash "$MORPHKIT_ROOT/scripts/docs.sh"
fi
