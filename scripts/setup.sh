#!/usr/bin/env bash
# Sourced by scripts/demo.sh and scripts/test.sh: installs what morphkit needs on a
# fresh Debian/Ubuntu machine, idempotently.
#   1. the system GL libraries via apt when missing (as root; otherwise it prints the
#      sudo line to run and stops): libosmesa6 (OSMesa, the default software platform),
#      libegl1 + libegl-mesa0 + libgbm1 (EGL: MORPHKIT_GL=egl, Mesa's software EGL on a
#      machine without a GPU; pyglet's headless mode loads libEGL too), libgl1 and
#      libopengl0 (the GL entry points pyglet and PyOpenGL load);
#   2. a virtual environment in .venv (python3 >= 3.10);
#   3. the morphkit package into it (editable), with extras given as $1 (e.g. "test");
#   4. numba's kernels compiled once into numba's on-disk cache (``cache=True``), so that no
#      later process (a test run, the demo, a bake worker) compiles them: about a minute the
#      first time on 2 busy cores, about 5 s (imports, a small bake and playback) once cached;
#   5. with the test extras: node and npm via apt when missing (as root), and the Khronos glTF
#      validator (npm's gltf-validator, pinned) into .cache/node, which the export tests run;
#      Debian's chromium and chromium-driver (the preview page's browser test, through selenium,
#      a test extra).
set -euo pipefail
MORPHKIT_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$MORPHKIT_ROOT"
extras="${1:-}"

need_apt=()
have_lib() { ldconfig -p 2>/dev/null | grep "$1" >/dev/null; }  # grep reads all: no SIGPIPE under pipefail
have_lib 'libOSMesa\.so' || need_apt+=(libosmesa6)
have_lib 'libEGL\.so\.1' || need_apt+=(libegl1)
have_lib 'libEGL_mesa\.so' || need_apt+=(libegl-mesa0)
have_lib 'libgbm\.so\.1' || need_apt+=(libgbm1)
have_lib 'libGL\.so\.1' || need_apt+=(libgl1)
have_lib 'libOpenGL\.so\.0' || need_apt+=(libopengl0)
if [ "$extras" = "test" ]; then
  command -v node >/dev/null 2>&1 || need_apt+=(nodejs)
  command -v npm >/dev/null 2>&1 || need_apt+=(npm)
  command -v chromium >/dev/null 2>&1 || need_apt+=(chromium)
  command -v chromedriver >/dev/null 2>&1 || need_apt+=(chromium-driver)
fi
if ! python3 -c 'import ensurepip, venv' >/dev/null 2>&1; then need_apt+=(python3-venv); fi
if [ "${#need_apt[@]}" -gt 0 ]; then
  if [ "$(id -u)" = "0" ]; then
    echo "morphkit setup: installing ${need_apt[*]} with apt-get"
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -qq
    apt-get install -y -qq "${need_apt[@]}" >/dev/null
  else
    echo "morphkit setup: missing system packages: ${need_apt[*]}. Run:" >&2
    echo "  sudo apt-get update && sudo apt-get install -y ${need_apt[*]}" >&2
    exit 1
  fi
fi

if [ ! -x .venv/bin/python ]; then
  echo "morphkit setup: creating .venv"
  python3 -m venv .venv
fi
spec="."
[ -n "$extras" ] && spec=".[${extras}]"
echo "morphkit setup: installing morphkit${extras:+[$extras]} into .venv"
.venv/bin/python -m pip install -q --disable-pip-version-check --upgrade pip >/dev/null
.venv/bin/python -m pip install -q --disable-pip-version-check -e "$spec"
export PATH="$MORPHKIT_ROOT/.venv/bin:$PATH"
echo "morphkit setup: numba kernels into the on-disk cache (once)"
.venv/bin/python -c 'from morphkit.bench.bake_suite import kernel_workload as w; r = w(); print("morphkit setup: %.1f s compiling %d kernels (0: all cached)" % (r["compile_s"], r["kernels"]))'
if [ "$extras" = "test" ] && [ ! -f .cache/node/node_modules/gltf-validator/package.json ]; then
  echo "morphkit setup: the glTF validator (npm gltf-validator@2.0.0-dev.3.10) into .cache/node"
  mkdir -p .cache/node
  npm install --prefix .cache/node --no-audit --no-fund --silent gltf-validator@2.0.0-dev.3.10 >/dev/null
fi
