#!/usr/bin/env bash
# Set everything up (see scripts/setup.sh, with the docs extras) and build the documentation
# into docs/_build/html: the API reference from the docstrings, the gallery (every sample in
# samples/ is run, headless), the technique pages with the figures of docs/RESULTS.md.
# Warnings are errors: a broken cross-reference or a public name without a docstring fails it.
# Extra arguments go to sphinx-build (e.g. -E to rebuild everything).
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/setup.sh" docs
python -m sphinx -W --keep-going -b html docs docs/_build/html "$@"
echo "morphkit docs: open $MORPHKIT_ROOT/docs/_build/html/index.html"
