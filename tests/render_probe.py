"""Renders fixed views on this process's GL platform and saves the depths (``tests/test_render_egl.py``).

Run as ``python tests/render_probe.py OUT.npz`` with ``MORPHKIT_GL`` set (the platform is
fixed when :mod:`morphkit.render` is imported, so each platform needs its own process).
Saved: ``plane_<projection>_<dist>`` (a plane facing the camera, 48 x 64, ``znear = 0.05``,
``zfar = 100``), ``cow_<projection>`` (the cow, 512 x 512, light-view fit), ``platform``
and ``renderer`` (:func:`morphkit.render.gl_info`). One renderer holds contexts of both
sizes and is closed at the end (the EGL display must survive closing the first context).
"""

from __future__ import annotations

import sys

import numpy as np
import trimesh

from morphkit.camera import look_at, orthographic, perspective
from morphkit.meshes import cow
from morphkit.render import Renderer, gl_info
from morphkit.scene import Item, PointLight, light_view

PLANE = trimesh.Trimesh([[-100, -100, 0], [100, -100, 0], [100, 100, 0], [-100, 100, 0]],
                        [[0, 1, 2], [0, 2, 3]], process=False)
DISTS = (0.5, 1.0, 3.0, 10.0, 50.0)


def main(out: str) -> None:
    depths = {}
    with Renderer() as r:
        for dist in DISTS:
            pose = look_at([0, 0, dist], [0, 0, 0], up=[0, 1, 0])
            cams = {"orthographic": orthographic(2, 1.5, (48, 64), pose, znear=0.05, zfar=100),
                    "perspective": perspective(np.deg2rad(50), (48, 64), pose, znear=0.05, zfar=100)}
            for proj, cam in cams.items():
                depths[f"plane_{proj}_{dist}"] = r.depth(cam, [Item(PLANE)])
        mesh = cow()
        corners = trimesh.bounds.corners(mesh.bounds)
        persp = light_view(PointLight([0.3, -0.2, 2.5]), corners, (512, 512))
        ortho = orthographic(1.6, 1.6, (512, 512), look_at([0.2, -2.0, 1.0], mesh.centroid, up=[0, 0, 1]),
                             znear=0.1, zfar=10)
        for proj, cam in (("perspective", persp), ("orthographic", ortho)):
            depths[f"cow_{proj}"] = r.depth(cam, [Item(mesh)])
    info = gl_info()
    np.savez(out, platform=info["platform"], renderer=str(info["renderer"]), **depths)
    print("closed", info["platform"], info["renderer"])


if __name__ == "__main__":
    main(sys.argv[1])
