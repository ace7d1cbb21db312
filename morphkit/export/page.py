"""One self-contained HTML page: the preview's program and three.js inlined, its data embedded.

:func:`page_html` assembles the page ``morphkit preview`` writes. The page loads nothing: three.js
(the npm package's files vendored in ``morphkit/data/web/three``, version :data:`THREE_VERSION`)
and the preview's program (``morphkit/data/web/preview.js``) are ES modules given to the page's
import map as ``data:`` URLs, and the data (:func:`morphkit.export.preview.preview_data`) is a JSON
block the program reads. So the file opens from disk (``file://``), with no server and no network,
in any browser with WebGL 2; without WebGL 2 it says so instead of drawing a blank canvas.

The page's byte count is written into it (``page_bytes``, shown on the page) after assembly: the
number is padded to a fixed width so that writing it does not change the count.
"""

from __future__ import annotations

import base64
import json
from importlib import resources
from typing import Any

__all__ = ["page_html", "THREE_VERSION", "web_file"]

#: The vendored three.js (``morphkit/data/web/three/README.md``).
THREE_VERSION = "0.170.0"

#: The placeholder of the page's byte count: a JSON string of fixed width.
_BYTES_SLOT = '"@@PAGE_BYTES@@@@@@"'

_TEMPLATE = """<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<title>morphkit: loading</title>
<meta name="viewport" content="width=device-width, initial-scale=1">
<meta name="generator" content="morphkit preview (three.js {three})">
<style>
html, body {{ margin: 0; height: 100%; overflow: hidden; background: rgb(34, 34, 34);
  color: rgb(238, 238, 238);
  font: 13px/1.35 system-ui, sans-serif; }}
canvas {{ display: block; }}
#panel {{ position: absolute; top: 8px; left: 8px; background: rgba(0,0,0,0.55); padding: 8px 10px;
  border-radius: 4px; max-width: 46em; }}
#figures {{ white-space: pre-wrap; margin: 0 0 6px 0; font-family: ui-monospace, monospace; }}
#message {{ display: none; position: absolute; top: 40%; left: 10%; right: 10%; padding: 16px;
  background: rgb(102, 17, 17); color: white; font-size: 16px; border-radius: 4px; }}
label {{ display: block; }}
</style>
<script type="importmap">{importmap}</script>
</head>
<body>
<canvas id="view"></canvas>
<div id="panel">
<pre id="figures">morphkit preview: loading</pre>
<label>sun azimuth <input id="sun-az" type="range" min="-180" max="180" step="1"></label>
<label>sun elevation <input id="sun-el" type="range" min="-10" max="90" step="1"></label>
</div>
<div id="message"></div>
<noscript><div style="padding:16px">This page draws with JavaScript and WebGL 2; both are off.
</div></noscript>
<script type="application/json" id="morphkit-data">{data}</script>
<script type="module">{program}</script>
</body>
</html>
"""


def web_file(name: str) -> str:
    """The text of one of the page's vendored or own files (``morphkit/data/web/NAME``).

    Parameters
    ----------
    name : str
        Its path under ``morphkit/data/web``, e.g. ``"three/three.module.min.js"``.

    Returns
    -------
    str
    """
    return resources.files("morphkit").joinpath("data", "web", *name.split("/")).read_text("utf-8")


def _module_url(source: str) -> str:
    return "data:text/javascript;base64," + base64.b64encode(source.encode("utf-8")).decode("ascii")


def page_html(data: dict[str, Any]) -> str:
    """The page for ``data`` (the module notes).

    Parameters
    ----------
    data : dict
        JSON values; ``page_bytes`` is set here.

    Returns
    -------
    str
        The HTML, ASCII (its length is its size in bytes).
    """
    loader = web_file("three/GLTFLoader.js").replace(
        "from '../utils/BufferGeometryUtils.js'", "from 'three/addons/utils/BufferGeometryUtils.js'")
    imports = {
        "three": _module_url(web_file("three/three.module.min.js")),
        "three/addons/utils/BufferGeometryUtils.js": _module_url(web_file("three/BufferGeometryUtils.js")),
        "three/addons/loaders/GLTFLoader.js": _module_url(loader),
    }
    body = dict(data)
    body["page_bytes"] = "@@PAGE_BYTES@@@@@@"
    text = json.dumps(body, ensure_ascii=True, separators=(",", ":")).replace("</", "<\\/")
    html = _TEMPLATE.format(three=THREE_VERSION, importmap=json.dumps({"imports": imports}),
                            data=text, program=web_file("preview.js").replace("</script", "<\\/script"))
    n = len(html.encode("utf-8"))
    slot = json.dumps(str(n).rjust(len(_BYTES_SLOT) - 2))
    return html.replace(_BYTES_SLOT, slot, 1)
