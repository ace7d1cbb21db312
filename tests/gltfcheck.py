"""The Khronos glTF validator (npm's ``gltf-validator``, installed by ``scripts/setup.sh test``) run on
a file the tests exported: its report, or a skip (a failure under ``MORPHKIT_REQUIRE_GLTF_VALIDATOR``)
where it is not installed."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
#: Where scripts/setup.sh installs the validator.
VALIDATOR = ROOT / ".cache" / "node" / "node_modules" / "gltf-validator"
VALIDATE_JS = ROOT / "scripts" / "gltf_validate.js"


def validate(path: Path) -> dict:
    """The validator's report of ``path``: ``errors``, ``warnings``, ``infos``, ``messages``."""
    node = shutil.which("node")
    if node is None or not VALIDATOR.is_dir():
        if os.environ.get("MORPHKIT_REQUIRE_GLTF_VALIDATOR"):
            pytest.fail(f"the glTF validator is not installed ({VALIDATOR}: scripts/setup.sh test)")
        pytest.skip("node and the glTF validator are not installed (scripts/setup.sh test installs them)")
    out = subprocess.run([node, str(VALIDATE_JS), str(path)], capture_output=True, text=True, timeout=120,
                         env={**os.environ, "NODE_PATH": str(VALIDATOR.parent)}, check=False)
    assert out.returncode == 0, out.stderr
    return json.loads(out.stdout)
