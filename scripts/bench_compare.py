#!/usr/bin/env python3
"""Compare two ``morphkit bench --json`` files of one suite: equal quality figures, time ratio.

Usage: ``python scripts/bench_compare.py BEFORE.json AFTER.json``

Rows are matched by method and parameters. Quality figures are every numeric metric except
timings, speed ratios and memory (names with ``ms``, ``*_s``, ``x_*``, ``vs_*``,
``flat``, ``mem_mb``); two are equal within
1e-9 relative. The time ratio is the geometric mean over matched rows of ``ms_median`` after /
before (rows above 0.05 ms): run both files back to back on one machine, interleaved, as the
machines are shared.
"""

from __future__ import annotations

import json
import math
import sys
from typing import Any

#: Rows faster than this (ms) are left out of the time ratio: timer noise.
MIN_MS = 0.05


def key(row: dict[str, Any]) -> tuple[str, str]:
    """A row's identity: its method and parameters."""
    return row["method"], json.dumps(row["params"], sort_keys=True)


def load(path: str) -> dict[tuple[str, str], dict[str, Any]]:
    """The rows of a bench JSON file by identity."""
    with open(path) as f:
        return {key(r): r for r in json.load(f)}


def is_quality(name: str, value: Any) -> bool:
    """Whether a metric is a quality figure (not a timing or memory)."""
    timing = ("ms" in name.split("_") or name.startswith(("ms", "x_", "vs_")) or name.endswith(("_ms", "_s"))
              or name in ("mem_mb", "flat"))  # x_*, vs_*: a speed ratio to a baseline; flat: time max/min
    return isinstance(value, int | float) and not isinstance(value, bool) and not timing


def main(before_path: str, after_path: str) -> str:
    """The comparison as one line."""
    before, after = load(before_path), load(after_path)
    common = sorted(set(before) & set(after))
    compared = differing = 0
    max_diff = 0.0
    for k in common:
        mb, ma = before[k]["metrics"], after[k]["metrics"]
        for name, v in mb.items():
            if not is_quality(name, v) or not is_quality(name, ma.get(name)):
                continue
            compared += 1
            d = abs(float(v) - float(ma[name]))
            if d > 1e-9 * max(1.0, abs(float(v))):
                differing += 1
                max_diff = max(max_diff, d)
    ratios = [after[k]["ms_median"] / before[k]["ms_median"] for k in common
              if (before[k]["ms_median"] or 0) > MIN_MS and (after[k]["ms_median"] or 0) > 0]
    gmean = math.exp(sum(map(math.log, ratios)) / len(ratios)) if ratios else float("nan")
    return (f"rows {len(common)} matched (before {len(before)}, after {len(after)}); quality values "
            f"{compared}, differing {differing} (largest difference {max_diff:.3g}); time after/before "
            f"{gmean:.3f} (geometric mean over {len(ratios)} rows above {MIN_MS} ms)")


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    print(main(sys.argv[1], sys.argv[2]))
