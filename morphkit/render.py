"""The rendering boundary: the only module of morphkit that imports pyrender.

Platform. :data:`morphkit.settings.GL_PLATFORM` picks the GL platform once per
process: ``osmesa`` (default; software, any Linux machine with ``libosmesa6``)
or ``egl`` (``MORPHKIT_GL=egl``: a GPU through its driver's EGL, or Mesa's
software EGL where there is none). ``PYOPENGL_PLATFORM`` is set from it before
pyrender (and PyOpenGL) are imported. :func:`gl_info` names the platform and
the GL renderer string in use (the benches record both).

Headless import. pyrender imports its pyglet viewer at import time, and pyglet
would load its X11 backend (``libX11``, ``libXrender``) and fail on a machine
without X11 client libraries. morphkit never opens a window: pyglet's
``headless`` option is set before pyrender is imported (pyglet then loads
``libEGL`` and ``libGL`` only). When the import fails, the error names the GL
library that could not be loaded and the package that provides it
(:func:`missing_gl_libraries`).

Everything returned from here is plain numpy in the conventions of
:mod:`morphkit.conventions`:

* depth images are float32 linear depth along the camera's viewing axis
  (OpenCV ``Z``) in scene units, background ``+inf``
  (:data:`~morphkit.conventions.BACKGROUND_DEPTH`);
* colour images are uint8 ``(H, W, 3)``; source views are uint8 RGBA with
  straight (not premultiplied) alpha equal to pixel coverage.

Depth linearisation. pyrender 0.1.45 (and its fork pyrender2) converts the
depth buffer to linear depth with the *perspective* formula
``d = 2 n f / (f + n - z_ndc (f - n))`` for every camera, which is wrong for
orthographic cameras (a plane at distance 0.5 with ``n = 0.05, f = 100``
comes back as 0.0502). morphkit does not trust that value for orthographic
views: it inverts pyrender's formula back to NDC depth and applies the
orthographic one, ``Z = (f + n + z_ndc (f - n)) / 2``, which simplifies to
``Z = f + n - n f / d``. Perspective depth is pyrender's value unchanged.
Tested against analytic planes in ``tests/test_render.py``.

Shader programs. pyrender caches its compiled shader programs under a key that
includes ``OpenGL.contextdata.getContext()``; with PyOpenGL >= 3.1.9 on OSMesa
that call returns a new pointer object every time, so the cache never hits and
every primitive of every frame compiled and linked a new program (and kept it:
one GL program per drawn item and frame).
Each context here gets a program cache keyed by the shaders and defines only
(``_ProgramCache``: one cache per context, so the context needs no key).

EGL. Two defects of pyrender's EGL path are corrected here (``_Offscreen``):

* its framebuffer path renders into a 4x multisampled buffer and blits one
  sample back, so depth (and the silhouette) is sampled off the pixel centre
  (about (+0.125, -0.375) px, reported on a GPU in issue #29; Mesa's EGL does the same);
  morphkit renders into single-sampled buffers: depth at pixel centres,
  identical to OSMesa's (``tests/test_render_egl.py``);
* its ``delete_context`` terminates the EGL display, which every context of the
  process shares: closing one context broke the others (a :class:`Renderer`
  with contexts of two image sizes died in :meth:`Renderer.close` with
  ``EGL_NOT_INITIALIZED``). Contexts are destroyed here without terminating the
  display (the driver frees it at process exit).

Contexts. An OSMesa context cannot resize its buffer, so one GL context (and
one ``pyrender.Scene`` with its uploaded meshes) is kept per image shape and
reused for every frame of that shape (on EGL too). Meshes are converted and uploaded once
per context; moving an object only changes its node pose.

Materials. An item with a colour is drawn as it always was: one
``MetallicRoughnessMaterial`` of that colour (``pyrender.Mesh.from_trimesh``
with that material, which drops the mesh's visuals). An item without one is
drawn in its mesh's own look (:func:`morphkit.look.mesh_look`), built here into
a ``pyrender.Primitive`` directly rather than by ``from_trimesh(material=None)``,
whose pitfalls it avoids: every material it makes is ``alphaMode='BLEND'``
(order-dependent blending) and single-sided, a trimesh ``SimpleMaterial``'s
default grey diffuse (0.4) darkens its texture, 16-bit textures wrap around in
``astype(uint8)``, greyscale ones crash, and RGB textures of a width that is
not a multiple of 4 upload skewed (``GL_UNPACK_ALIGNMENT``). Here textures are
RGBA uint8 (:func:`morphkit.texture.texture_rgba`), materials ``OPAQUE`` or
``MASK`` and two-sided, and cut-outs are drawn by morphkit's copies of three
pyrender fragment shaders (``morphkit/data/shaders``; pyrender's shaders ignore
``alphaMode`` and ``alphaCutoff``) that discard fragments with base-colour
alpha below 0.5: a look with cutoff ``c`` uploads its factor alpha times
``0.5 / c``, an opaque look all alphas at 1, so one shader serves every cutoff.
The same copies decode vertex colours from sRGB before lighting and draw the
normals pass. Items without texture or vertex colours keep pyrender's own
lit shader (their lit pixels are those of earlier versions); every flat draw
(the albedo pass) uses morphkit's ``flat.frag``, which takes the base colour in
linear light (factor x decoded texel x decoded vertex colour) and writes it
sRGB-encoded (:mod:`morphkit.conventions`, "Colour"). ``DEPTH_ONLY`` draws
ignore materials (no cut-outs) and always cull back faces (pyrender), dropping
an open surface seen from behind that the two-sided colour draw shows. So a
depth image with a cut-out item, or a mesh that is not a :func:`~morphkit.meshes.closed_volume`
(decided once per mesh, by the first depth image showing it), in view is taken
from a flat colour draw (no culling; same vertex transform, so the same depth).
Closed volumes keep ``DEPTH_ONLY``: seen from outside, their front faces hide
every back face (depth bit-identical). Known limit: a camera inside a closed
volume, or a near plane cutting one, sees back faces that this draw drops.
"""

from __future__ import annotations

import os
from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import Any

import cv2
import numpy as np
import trimesh

from . import tol
from .camera import CameraModel
from .conventions import BACKGROUND_DEPTH, gl_pose_from_cv
from .errors import RenderError, ValidationError, expected_got
from .glplatform import GL_LIBRARIES, check_gl_memory, explain_gl_failure, missing_gl_libraries
from .look import DIELECTRIC, SurfaceLook, mesh_look
from .meshes import closed_volume
from .passes import RenderPasses, area_straight, as_uint8, decode_normals, supersampled_camera
from .scene import AreaLight, DirectionalLight, Item, Light, PointLight
from .settings import EGL_DEVICE, GL_PLATFORM, select_gl_platform
from .validate import as_int

__all__ = ["Renderer", "RenderPasses", "SHADER_DIR", "closed_volume", "gl_info", "missing_gl_libraries",
           "GL_LIBRARIES"]

def _headless_pyglet() -> None:
    """pyglet without its X11 backend (see the module docstring); before pyrender is imported."""
    try:
        import pyglet
    except ImportError:  # pragma: no cover - pyglet comes with pyrender
        return
    pyglet.options["headless"] = True
    pyglet.options["shadow_window"] = False


try:
    select_gl_platform()  # PYOPENGL_PLATFORM for PyOpenGL; must precede the first OpenGL import
    _headless_pyglet()
    import pyrender
    from OpenGL import GL as _GL

    if GL_PLATFORM == "egl":
        from pyrender.platforms import egl as _platform_egl
    else:
        from pyrender.platforms import osmesa as _platform_osmesa
except Exception as exc:  # pragma: no cover - depends on the machine (tested in subprocesses)
    _IMPORT_ERROR: Exception | None = exc
    pyrender = None
else:
    _IMPORT_ERROR = None

#: GL strings read from the first context this process created (see :func:`gl_info`).
_GL_STRINGS: dict[str, str] = {}

#: morphkit's copies of pyrender's fragment shaders (package data; module notes, "Materials").
SHADER_DIR = Path(__file__).resolve().parent / "data" / "shaders"
#: Faces above which a mesh is drawn with smooth (vertex) normals: flat shading repeats
#: every vertex per face, tripling a 1M-face mesh (face colours are always flat).
_SMOOTH_FACES = 20000


if pyrender is not None:
    class _MatrixCamera(pyrender.Camera):
        """A pyrender camera with morphkit's projection matrix.

        pyrender's own cameras cannot express every CameraModel: its
        OrthographicCamera ignores ``xmag`` (it forces square pixels from the
        viewport's aspect), and off-centre principal points need
        IntrinsicsCamera. :meth:`CameraModel.gl_projection` covers both.
        """

        def __init__(self, projection: np.ndarray, znear: float, zfar: float) -> None:
            super().__init__(znear=znear, zfar=zfar)
            self._P = np.asarray(projection, dtype=np.float64)

        def get_projection_matrix(self, width: int | None = None, height: int | None = None
                                  ) -> np.ndarray:
            return self._P.copy()

    class _ProgramCache(pyrender.shader_program.ShaderProgramCache):
        """pyrender's shader-program cache, keyed without the GL context handle.

        pyrender keys each compiled program by ``OpenGL.contextdata.getContext()``,
        which under OSMesa is a new pointer object on every call: the key never
        matched, so every colour render compiled its programs again and kept the
        old ones (a leak and a recompile on every render; figures in ``docs/RESULTS.md``).
        Each :class:`_Context` has its own renderer and cache, so the context is
        implicit in the cache.
        """

        #: When set, flat draws use morphkit's normals shader (the normals pass).
        normals: bool = False

        def _path(self, name: str | None, defines: dict) -> str | None:
            """The file of shader ``name``: morphkit's copy for every flat draw (albedo; the
            normals pass) and for lit textured or vertex-coloured primitives, pyrender's otherwise."""
            if name is None:
                return None
            if name == "flat.frag":
                return str(SHADER_DIR / ("normals.frag" if self.normals else "flat.frag"))
            if name == "mesh.frag" and ("HAS_BASE_COLOR_TEX" in defines or "COLOR_0_LOC" in defines):
                return str(SHADER_DIR / name)
            return os.path.join(self.shader_dir, name)

        def get_program(self, vertex_shader: str, fragment_shader: str, geometry_shader: str | None = None,
                        defines: dict | None = None) -> pyrender.shader_program.ShaderProgram:
            defines = {} if defines is None else defines
            vs, fs, gs = (self._path(f, defines) for f in (vertex_shader, fragment_shader, geometry_shader))
            key = (vs, fs, gs, tuple(sorted(defines.items())))
            program = self._program_cache.get(key)
            if program is None:
                program = self._program_cache[key] = pyrender.shader_program.ShaderProgram(
                    vertex_shader=vs, fragment_shader=fs, geometry_shader=gs, defines=defines)
            return program

    class _SingleSampleRenderer(pyrender.Renderer):
        """pyrender's renderer with single-sampled offscreen buffers (EGL's framebuffer path).

        pyrender allocates its "multisample" colour and depth buffers with 4 samples and
        blits them into single-sampled ones: the depth read back is one sub-sample, off
        the pixel centre. Here they are re-allocated with 0 samples right after pyrender
        creates them, so the blit is an exact copy of depth rasterised at pixel centres.
        Its shader programs are cached per context (``_ProgramCache``).
        """

        def __init__(self, width: int, height: int) -> None:
            super().__init__(width, height)
            self._program_cache = _ProgramCache()
            self._single_sampled: tuple[Any, Any] | None = None

        def _configure_main_framebuffer(self) -> None:
            super()._configure_main_framebuffer()
            buffers = (self._main_cb_ms, self._main_db_ms)
            if self._single_sampled != buffers:
                w, h = self._main_fb_dims
                for rb, fmt in zip(buffers, (_GL.GL_RGBA, _GL.GL_DEPTH_COMPONENT24), strict=True):
                    _GL.glBindRenderbuffer(_GL.GL_RENDERBUFFER, rb)
                    _GL.glRenderbufferStorageMultisample(_GL.GL_RENDERBUFFER, 0, fmt, w, h)
                self._single_sampled = buffers

    if GL_PLATFORM == "egl":
        class _EGLPlatform(_platform_egl.EGLPlatform):
            """pyrender's EGL platform, whose contexts are closed without terminating the display."""

            def delete_context(self) -> None:
                from OpenGL import EGL

                if self._egl_display is not None and self._egl_context is not None:
                    EGL.eglMakeCurrent(self._egl_display, EGL.EGL_NO_SURFACE, EGL.EGL_NO_SURFACE,
                                       EGL.EGL_NO_CONTEXT)
                    EGL.eglDestroyContext(self._egl_display, self._egl_context)
                self._egl_context = None
                self._egl_display = None  # shared by every context: not terminated

    class _Offscreen(pyrender.OffscreenRenderer):
        """pyrender's offscreen renderer on :data:`~morphkit.settings.GL_PLATFORM`, with the
        corrected EGL platform and renderer (see the module docstring) and per-context shader
        cache (``_ProgramCache``)."""

        def _create(self) -> None:
            w, h = self.viewport_width, self.viewport_height
            if GL_PLATFORM == "egl":
                self._platform = _EGLPlatform(w, h, device=_platform_egl.get_device_by_index(EGL_DEVICE))
            else:
                self._platform = _platform_osmesa.OSMesaPlatform(w, h)
            self._platform.init_context()
            self._platform.make_current()
            if not _GL_STRINGS:
                for key, name in (("renderer", _GL.GL_RENDERER), ("version", _GL.GL_VERSION),
                                  ("vendor", _GL.GL_VENDOR)):
                    value = _GL.glGetString(name)
                    _GL_STRINGS[key] = value.decode("utf-8", "replace") if value else ""
            self._renderer = _SingleSampleRenderer(w, h)

    def _flat_color_mesh(mesh: trimesh.Trimesh, color: tuple[float, ...]) -> pyrender.Mesh:
        """One colour: pyrender's ``from_trimesh`` with one material (drops the mesh's visuals)."""
        mat = pyrender.MetallicRoughnessMaterial(
            baseColorFactor=[*color, 1.0], metallicFactor=DIELECTRIC[0], roughnessFactor=DIELECTRIC[1],
            doubleSided=True)
        # Flat shading for small meshes (boxes look right); smooth for large ones
        # (flat shading would triple the vertex count of a 1M-face mesh).
        return pyrender.Mesh.from_trimesh(mesh, material=mat, smooth=len(mesh.faces) > _SMOOTH_FACES)

    def _look_mesh(mesh: trimesh.Trimesh, look: SurfaceLook) -> pyrender.Mesh:
        """A mesh's own look as one primitive (module notes, "Materials")."""
        smooth = len(mesh.faces) > _SMOOTH_FACES and look.face_colors is None
        faces = np.asarray(mesh.faces)
        if smooth:
            positions, normals, indices = mesh.vertices, mesh.vertex_normals, faces
            per_vertex = (lambda a: a)  # noqa: E731
        else:
            positions = mesh.vertices[faces].reshape(-1, 3)
            normals = np.repeat(mesh.face_normals, 3, axis=0)
            indices = None
            per_vertex = (lambda a: a[faces].reshape(-1, a.shape[1]))  # noqa: E731
        colors = None
        if look.vertex_colors is not None:
            colors = per_vertex(look.vertex_colors)
        elif look.face_colors is not None:
            colors = np.repeat(look.face_colors, 3, axis=0)
        texture, uv = look.texture, look.uv
        if texture is None and look.masked:  # a cut-out without a texture: the shader's alpha test
            texture, uv = np.full((1, 1, 4), 255, np.uint8), np.zeros((len(mesh.vertices), 2))
        factor = list(look.base_color)
        if look.masked:  # one shader test (alpha < 0.5) for every cutoff
            factor[3] *= 0.5 / max(float(look.alpha_cutoff), tol.ALPHA_FLOOR)
        tex = None if texture is None else pyrender.Texture(
            source=texture, source_channels="RGBA", sampler=pyrender.Sampler())
        mat = pyrender.MetallicRoughnessMaterial(
            baseColorFactor=factor, baseColorTexture=tex, metallicFactor=look.metallic,
            roughnessFactor=look.roughness, doubleSided=True,
            alphaMode="MASK" if look.masked else "OPAQUE", alphaCutoff=look.alpha_cutoff)
        prim = pyrender.Primitive(
            positions=np.asarray(positions, np.float32), normals=np.asarray(normals, np.float32),
            texcoord_0=None if uv is None else np.asarray(per_vertex(uv), np.float32),
            color_0=None if colors is None else colors.astype(np.float32) / 255.0,
            indices=indices, material=mat, mode=pyrender.constants.GLTF.TRIANGLES)
        return pyrender.Mesh(primitives=[prim])


def gl_info(*, open_context: bool = True) -> dict[str, str | None]:
    """The GL platform and the renderer string in use (the benches write both into their JSON rows).

    Reads ``GL_RENDERER``, ``GL_VERSION`` and ``GL_VENDOR`` from the first context this process
    created; when none was created yet, creates a small one to read them (and closes it), unless
    ``open_context`` is False.

    Parameters
    ----------
    open_context : bool, optional
        Create a context to read the strings when this process has none yet (default True).

    Returns
    -------
    dict of str to str or None
        ``platform`` (``"osmesa"`` or ``"egl"``), ``renderer`` (e.g. ``"llvmpipe (LLVM 15.0.6,
        256 bits)"`` or the GPU's name), ``version``, ``vendor``; the three GL strings are None
        when no context was read (with ``error`` saying why when one could not be created).
    """
    info: dict[str, str | None] = {"platform": GL_PLATFORM}
    if not _GL_STRINGS and open_context:
        try:
            if pyrender is None:
                raise RenderError(explain_gl_failure(_IMPORT_ERROR or RuntimeError("pyrender not imported")))
            _Offscreen(8, 8).delete()
        except Exception as exc:  # noqa: BLE001 - reported, not raised: a bench row still gets written
            return {**info, "renderer": None, "version": None, "vendor": None, "error": repr(exc)}
    if not _GL_STRINGS:
        return {**info, "renderer": None, "version": None, "vendor": None}
    return {**info, **_GL_STRINGS}


class _Context:
    """One GL context of a fixed shape with its scene and node cache.

    Each (mesh, look) is converted and uploaded once (one ``pyrender.Mesh``; the
    look is the item's colour, or the mesh's own look for ``color=None``);
    several :class:`~morphkit.scene.Item` s sharing it (instances of one mesh at
    several poses) get one node each, all referring to that uploaded mesh.
    """

    def __init__(self, shape: tuple[int, int]) -> None:
        h, w = shape
        check_gl_memory(shape)
        try:
            self.renderer = _Offscreen(viewport_width=w, viewport_height=h)
        except Exception as exc:
            raise RenderError(f"cannot create an offscreen GL context of shape {shape}: "
                              f"{explain_gl_failure(exc)}") from exc
        self.scene = pyrender.Scene(bg_color=[0.0, 0.0, 0.0, 0.0], ambient_light=[0.0, 0.0, 0.0])
        # id(trimesh) -> (trimesh kept alive, {look key: [node, ...]}): node 0 stays in the scene
        # (hidden through its mesh's visibility), further instance nodes are added when needed;
        # the look key is the item's colour, or "own" for the mesh's own look
        self.nodes: dict[int, tuple[trimesh.Trimesh, dict[tuple[float, ...] | str, list[pyrender.Node]]]] = {}
        # id(pool) -> whether its depth needs a flat colour draw (module notes, "Materials"): a
        # cut-out at once, else decided by the first depth() that shows it (closed_volume)
        self.flat_depth: dict[int, bool] = {}
        self.pool_mesh: dict[int, trimesh.Trimesh] = {}
        self.shown: list[int] = []  # id(pool) of the uploads shown
        self.cam_node: pyrender.Node | None = None
        self.light_nodes: list[pyrender.Node] = []

    def _pool(self, item: Item) -> list[pyrender.Node]:
        key = id(item.mesh)
        entry = self.nodes.get(key)
        if entry is None or entry[0] is not item.mesh:
            entry = (item.mesh, {})
            self.nodes[key] = entry
        key = "own" if item.color is None else tuple(float(c) for c in item.color)
        pool = entry[1].get(key)
        if pool is None:
            if item.color is not None:
                pm = _flat_color_mesh(item.mesh, key)
            else:
                look = mesh_look(item.mesh)
                pm = _flat_color_mesh(item.mesh, look.base_color[:3]) if look.plain else \
                    _look_mesh(item.mesh, look)
            pool = entry[1][key] = [self.scene.add(pm, pose=np.eye(4))]
            self.pool_mesh[id(pool)] = item.mesh
            if item.color is None and look.masked:
                self.flat_depth[id(pool)] = True
        return pool

    def show(self, items: Sequence[Item]) -> None:
        groups: dict[int, tuple[list[pyrender.Node], list[Item]]] = {}
        for it in items:
            pool = self._pool(it)
            groups.setdefault(id(pool), (pool, []))[1].append(it)
        self.shown = list(groups)
        for _mesh, by_color in self.nodes.values():
            for pool in by_color.values():
                used = groups.get(id(pool), (pool, []))[1]
                pool[0].mesh.is_visible = bool(used)
                while len(pool) < len(used):  # one more instance of this mesh: share its upload
                    pool.append(self.scene.add(pool[0].mesh, pose=np.eye(4)))
                for k, node in enumerate(pool):
                    if k < len(used):
                        if k > 0 and not self.scene.has_node(node):
                            self.scene.add_node(node)
                        self.scene.set_pose(node, np.asarray(used[k].pose, dtype=np.float64))
                    elif k > 0 and self.scene.has_node(node):
                        self.scene.remove_node(node)

    def depth_needs_flat_draw(self) -> bool:
        """Whether an upload shown has cut-outs or is not a closed volume (decided once each)."""
        for k in self.shown:
            if k not in self.flat_depth:
                self.flat_depth[k] = not closed_volume(self.pool_mesh[k])
        return any(self.flat_depth[k] for k in self.shown)

    def set_camera(self, camera: CameraModel) -> None:
        cam = _MatrixCamera(camera.gl_projection(), camera.znear, camera.zfar)
        if self.cam_node is not None:
            self.scene.remove_node(self.cam_node)
        self.cam_node = self.scene.add(cam, pose=camera.gl_pose())

    @property
    def programs(self) -> _ProgramCache:
        """This context's shader-program cache (installed in ``__init__``)."""
        return self.renderer._renderer._program_cache  # noqa: SLF001

    def set_lights(self, lights: Iterable[Light], ambient: float) -> None:
        for n in self.light_nodes:
            self.scene.remove_node(n)
        self.light_nodes = []
        self.scene.ambient_light = np.full(3, float(ambient))
        for light in lights:
            for pl in _as_pyrender_lights(light):
                self.light_nodes.append(self.scene.add(pl[0], pose=pl[1]))


def _as_pyrender_lights(light: Light) -> list[tuple[pyrender.Light, np.ndarray]]:
    if isinstance(light, DirectionalLight):
        from .camera import look_at

        pose = gl_pose_from_cv(look_at(np.zeros(3), light.direction))  # GL -z = direction
        return [(pyrender.DirectionalLight(color=np.ones(3), intensity=light.intensity), pose)]
    if isinstance(light, PointLight):
        T = np.eye(4)
        T[:3, 3] = light.position
        return [(pyrender.PointLight(color=np.ones(3), intensity=light.intensity), T)]
    if isinstance(light, AreaLight):
        out = []
        for p in light.point_lights(2):
            out += _as_pyrender_lights(p)
        return out
    raise ValidationError(expected_got("light", "a DirectionalLight, PointLight or AreaLight",
                                       type(light).__name__))


class Renderer:
    """A reusable headless renderer (create once, render many frames).

    Creating a GL context costs far more than rendering a frame in it (``morphkit
    bench render``). Keep one :class:`Renderer` for a whole session; it keeps one
    context per image shape. Call :meth:`close` (or use ``with``) to free GL.
    """

    def __init__(self) -> None:
        if pyrender is None:
            raise RenderError(f"pyrender is not importable: {explain_gl_failure(_IMPORT_ERROR)}")
        self._contexts: dict[tuple[int, int], _Context] = {}

    def __enter__(self) -> Renderer:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def close(self) -> None:
        """Free every GL context."""
        for ctx in self._contexts.values():
            ctx.renderer.delete()
        self._contexts.clear()

    def _ctx(self, camera: CameraModel) -> _Context:
        if not isinstance(camera, CameraModel):
            raise ValidationError(expected_got("camera", "a morphkit CameraModel", type(camera).__name__))
        ctx = self._contexts.get(camera.shape)
        if ctx is None:
            ctx = self._contexts[camera.shape] = _Context(camera.shape)
        return ctx

    @staticmethod
    def _check_items(items: Sequence[Item]) -> Sequence[Item]:
        for it in items:
            if not isinstance(it, Item):
                raise ValidationError(expected_got("items", "a sequence of morphkit.render.Item",
                                                   type(it).__name__))
        return items

    def _linear_depth(self, raw: np.ndarray, camera: CameraModel) -> np.ndarray:
        d = np.asarray(raw, dtype=np.float64)
        bg = d <= 0.0  # pyrender writes 0 where nothing was drawn
        if camera.projection == "orthographic":
            n, f = camera.znear, camera.zfar
            with np.errstate(divide="ignore"):
                d = f + n - n * f / np.where(bg, 1.0, d)
        out = d.astype(np.float32)
        out[bg] = BACKGROUND_DEPTH
        return out

    def pyrender_depth(self, camera: CameraModel, items: Sequence[Item]) -> np.ndarray:
        """pyrender's own depth output, uncorrected (background 0; orthographic
        values wrong, see the module docstring). For comparisons only: use :meth:`depth`.

        Parameters
        ----------
        camera : CameraModel
            The view.
        items : sequence of Item
            Items to draw, world poses.

        Returns
        -------
        (H, W) float32
            pyrender's depth, ``0`` background.
        """
        ctx = self._ctx(camera)
        ctx.show(self._check_items(items))
        ctx.set_camera(camera)
        return ctx.renderer.render(ctx.scene, flags=pyrender.RenderFlags.DEPTH_ONLY)

    def depth(self, camera: CameraModel, items: Sequence[Item]) -> np.ndarray:
        """Linear depth ``(H, W)`` float32 of ``items`` seen by ``camera``; background ``+inf``.

        Cut-out texels are holes, and every surface is two-sided: an open surface (a card, a
        quad) seen from behind has depth, as in the colour draw (with a cut-out item, or a mesh
        that is not a closed outward-facing volume, in view the depth comes from a flat colour
        draw: module notes, "Materials").

        Parameters
        ----------
        camera : CameraModel
            The view.
        items : sequence of Item
            Items to draw, world poses.

        Returns
        -------
        (H, W) float32
            Linear depth, ``+inf`` background.
        """
        ctx = self._ctx(camera)
        ctx.show(self._check_items(items))
        if ctx.depth_needs_flat_draw():
            return self._linear_depth(self._flat(ctx, camera, normals=False)[1], camera)
        return self._linear_depth(self.pyrender_depth(camera, items), camera)

    def _flat(self, ctx: _Context, camera: CameraModel, *, normals: bool) -> tuple[np.ndarray, np.ndarray]:
        """A flat draw (albedo, or encoded normals) of the items shown: RGB uint8 and pyrender's
        depth (0 where nothing is drawn)."""
        ctx.set_camera(camera)
        ctx.scene.bg_color = np.zeros(4)
        ctx.programs.normals = normals
        try:
            color, raw = ctx.renderer.render(ctx.scene, flags=pyrender.RenderFlags.FLAT)
        finally:
            ctx.programs.normals = False
        return np.ascontiguousarray(color[..., :3]), raw

    def albedo(self, camera: CameraModel, items: Sequence[Item]) -> np.ndarray:
        """Unlit base colour ``(H, W, 3)`` uint8 of ``items``: factor x texture x vertex colour in
        linear light, sRGB-encoded (:mod:`morphkit.conventions`, "Colour"), 0 where nothing is drawn.

        Parameters
        ----------
        camera : CameraModel
            The view.
        items : sequence of Item
            Items to draw, world poses.

        Returns
        -------
        (H, W, 3) uint8
            Albedo.
        """
        ctx = self._ctx(camera)
        ctx.show(self._check_items(items))
        return self._flat(ctx, camera, normals=False)[0]

    def normals(self, camera: CameraModel, items: Sequence[Item]) -> np.ndarray:
        """World-frame unit normals ``(H, W, 3)`` float32 of the surfaces facing ``camera``,
        0 where nothing is drawn (8-bit encoded on the way: at most
        :data:`~morphkit.conventions.NORMAL_ENCODING_DEG` off).

        Parameters
        ----------
        camera : CameraModel
            The view.
        items : sequence of Item
            Items to draw, world poses.

        Returns
        -------
        (H, W, 3) float32
            Unit normals, world frame.
        """
        ctx = self._ctx(camera)
        ctx.show(self._check_items(items))
        enc, raw = self._flat(ctx, camera, normals=True)
        return decode_normals(enc, raw > tol.PYRENDER_BACKGROUND)

    def passes(self, camera: CameraModel, items: Sequence[Item], lights: Iterable[Light], *,
               ambient: float = 0.35, background: tuple[float, float, float] = (0.0, 0.0, 0.0),
               ) -> RenderPasses:
        """Lit colour, albedo, normals, depth and coverage of one view (three draws).

        Parameters
        ----------
        camera : CameraModel
            The view.
        items : sequence of Item
            Items to draw, world poses.
        lights : iterable of Light
            Lights, world frame.
        ambient : float, optional
            Ambient light level.
        background : tuple of 3 float, optional
            RGB in ``[0, 1]`` of the lit colour where nothing is drawn.

        Returns
        -------
        RenderPasses
            The passes; ``alpha`` is 1 where a surface is drawn, else 0.
        """
        color, depth = self.color_depth(camera, items, lights, ambient=ambient, background=background)
        ctx = self._ctx(camera)
        albedo = self._flat(ctx, camera, normals=False)[0]
        enc = self._flat(ctx, camera, normals=True)[0]
        covered = np.isfinite(depth)
        return RenderPasses(color, albedo, decode_normals(enc, covered), depth, covered.astype(np.float32))

    def source_passes(self, camera: CameraModel, items: Sequence[Item], lights: Iterable[Light], *,
                      ambient: float = 0.35, supersample: int = 3) -> RenderPasses:
        """:meth:`passes` drawn at ``supersample`` times the resolution and area-averaged, as
        :meth:`source_view` (for bakes): ``alpha`` is pixel coverage, colour and albedo are
        straight alpha, normals the renormalised mean over the covered samples, depth the
        nearest covered sample's (``+inf`` where none is covered).

        Parameters
        ----------
        camera : CameraModel
            The view.
        items : sequence of Item
            Items to draw, world poses.
        lights : iterable of Light
            Lights, world frame.
        ambient : float, optional
            Ambient light level.
        supersample : int, optional
            Supersampling factor per axis.

        Returns
        -------
        RenderPasses
            The passes at ``camera.shape``.
        """
        s = as_int(supersample, "supersample", lo=1)
        h, w = camera.shape
        big = self.passes(supersampled_camera(camera, s), items, lights, ambient=ambient)
        cov = big.alpha
        alpha = cv2.resize(cov, (w, h), interpolation=cv2.INTER_AREA)
        color = as_uint8(area_straight(big.color, cov, alpha, (h, w)))
        albedo = as_uint8(area_straight(big.albedo, cov, alpha, (h, w)))
        n = cv2.resize(big.normal, (w, h), interpolation=cv2.INTER_AREA)
        norm = np.linalg.norm(n, axis=-1, keepdims=True)
        n = np.where((alpha[..., None] > 0) & (norm > 0), n / np.maximum(norm, tol.ALPHA_FLOOR), 0.0)
        depth = big.depth.reshape(h, s, w, s).min(axis=(1, 3))
        return RenderPasses(color, albedo, n.astype(np.float32), depth, alpha.astype(np.float32))

    def color_depth(self, camera: CameraModel, items: Sequence[Item], lights: Iterable[Light],
                    *, ambient: float = 0.35,
                    background: tuple[float, float, float] = (0.0, 0.0, 0.0),
                    ) -> tuple[np.ndarray, np.ndarray]:
        """Shaded colour ``(H, W, 3)`` uint8 and linear depth ``(H, W)`` float32.

        No shadows are drawn (shadows are morphkit's job); ``ambient`` is the
        ambient light level (same for R, G, B); ``background`` is the RGB colour
        in [0, 1] where nothing is drawn.

        Parameters
        ----------
        camera : CameraModel
            The view.
        items : sequence of Item
            Items to draw, world poses.
        lights : iterable of Light
            Lights, world frame.
        ambient : float, optional
            Ambient light level.
        background : tuple of 3 float, optional
            RGB in ``[0, 1]`` where nothing is drawn.

        Returns
        -------
        color : (H, W, 3) uint8
            Shaded RGB.
        depth : (H, W) float32
            Linear depth, ``+inf`` background.
        """
        ctx = self._ctx(camera)
        ctx.show(self._check_items(items))
        ctx.set_camera(camera)
        ctx.set_lights(lights, ambient)
        ctx.scene.bg_color = np.array([*background, 0.0])
        color, raw = ctx.renderer.render(ctx.scene, flags=pyrender.RenderFlags.NONE)
        return np.ascontiguousarray(color[..., :3]), self._linear_depth(raw, camera)

    def source_view(self, camera: CameraModel, items: Sequence[Item], lights: Iterable[Light], *,
                    ambient: float = 0.35, supersample: int = 3) -> np.ndarray:
        """RGBA ``(H, W, 4)`` uint8 of ``items`` alone on a transparent background.

        Alpha is pixel coverage, measured by rendering at ``supersample`` times
        the resolution and area-averaging (OSMesa has no multisampling); colour
        is straight (un-premultiplied) alpha.

        Parameters
        ----------
        camera : CameraModel
            The view.
        items : sequence of Item
            Items to draw, world poses.
        lights : iterable of Light
            Lights, world frame.
        ambient : float, optional
            Ambient light level.
        supersample : int, optional
            Supersampling factor per axis.

        Returns
        -------
        (H, W, 4) uint8
            Straight-alpha RGBA.
        """
        s = int(supersample)
        if s < 1:
            raise ValidationError(expected_got("supersample", "an int >= 1", supersample))
        h, w = camera.shape
        color, depth = self.color_depth(supersampled_camera(camera, s), items, lights, ambient=ambient)
        cov = np.isfinite(depth).astype(np.float32)
        alpha = cv2.resize(cov, (w, h), interpolation=cv2.INTER_AREA)
        out = np.empty((h, w, 4), np.uint8)
        out[..., :3] = as_uint8(area_straight(color, cov, alpha, (h, w)))
        out[..., 3] = as_uint8(alpha * 255)
        return out
