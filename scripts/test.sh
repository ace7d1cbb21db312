#!/usr/bin/env bash
# Set everything up (see scripts/setup.sh, with the test extras) and run the test
# suite (with the doctests of the modules listed in pyproject.toml) and the linter,
# the numeric core once more under another OpenBLAS kernel (x86-64), then build the
# documentation with warnings as errors (scripts/docs.sh).
# Extra arguments go to pytest (e.g. -m "not gl"); with them, the docs are not built
# (the gallery needs GL, and a subset of the tests is not a full check).
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/setup.sh" test
ruff check morphkit tests samples docs
export MORPHKIT_REQUIRE_GLTF_VALIDATOR=1  # setup installed it: the export tests may not skip it
export MORPHKIT_REQUIRE_BROWSER=1  # and chromium: the preview's browser tests may not skip it
python -m pytest -q "$@"
if [ "$#" -eq 0 ]; then
  # the numeric core again under another OpenBLAS kernel: a result that flips with the last
  # bits of a matrix product is a bug in the geometry. Prescott (SSE3) runs on every x86-64
  # CPU (where the machine sets Prescott already, the first run was that kernel). The core:
  # correspondences and view morphs, billboard bakes, the mesh warp, cameras, shadow lookups,
  # reprojection, splats and the ray-cast truth (GL tests among them: bakes render).
  if [ "$(uname -m)" = "x86_64" ] && [ "${OPENBLAS_CORETYPE:-}" != "Prescott" ]; then
    echo "morphkit tests: the numeric core again under OPENBLAS_CORETYPE=Prescott"
    t=tests
    OPENBLAS_CORETYPE=Prescott python -m pytest -q -p no:cacheprovider \
      $t/test_viewmorph_*.py $t/test_billboard_look.py $t/test_billboard_asset.py \
      $t/test_billboard_geometry.py $t/test_billboard_ring.py $t/test_billboard_coverage.py \
      $t/test_warp.py $t/test_warp_accumulate.py $t/test_camera.py $t/test_metrics.py \
      $t/test_shadow_lookup.py $t/test_shadow_pixels.py $t/test_shadow_atlas.py $t/test_shadow_frame.py \
      $t/test_shadow_soft.py $t/test_shadow_penumbra.py $t/test_reproject.py $t/test_groundtruth.py \
      $t/test_fieldshadow.py $t/test_fieldsplat_quads.py $t/test_fieldsplat_levels.py \
      $t/test_sunatlas.py $t/test_dome.py $t/test_impostor.py $t/test_litmodes.py \
      $t/test_gltfscene.py $t/test_errortable.py
  fi
  # the rendering tests again on Mesa's EGL (software; the platform a GPU uses): MORPHKIT_GL=egl
  MORPHKIT_GL=egl python -m pytest -q -p no:cacheprovider tests/test_render.py
  bash "$MORPHKIT_ROOT/scripts/docs.sh"
fi
