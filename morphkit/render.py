"""The rendering boundary: the only module of morphkit that imports pyrender.

Platform and headless import: :mod:`morphkit.glplatform`; :func:`gl_info`: platform and GL renderer.

Everything returned from here is plain numpy in the conventions of :mod:`morphkit.conventions`:
depth images are float32 linear depth along the camera's viewing axis (OpenCV ``Z``) in scene units,
background ``+inf`` (pyrender's is wrong for orthographic cameras:
:func:`morphkit.passes.linear_depth` corrects it; tested against analytic planes in
``tests/test_render.py``); colour images are uint8 ``(H, W, 3)``; source views uint8 RGBA, straight
(not premultiplied) alpha equal to pixel coverage.

EGL. Two defects of pyrender's EGL path are corrected here (``_Offscreen``): its framebuffer path rendered
into a 4x multisampled buffer and blitted one sample back (depth and silhouettes off the pixel centre by
about (+0.125, -0.375) px): morphkit's buffers are single-sampled, depth at pixel centres as
OSMesa's (``tests/test_render_egl.py``); its ``delete_context`` terminated the EGL display every context
shares (closing one broke the others): it is not terminated here.

Contexts. An OSMesa context cannot resize its buffer, so one GL context (and one ``pyrender.Scene`` with its
uploaded meshes) is kept per image shape and reused for every frame of that shape (on EGL too). Meshes are
uploaded once per context; moving an object only changes its node pose. Shader programs: one cache per
context, keyed by the shaders and defines only (``_ProgramCache``).

Materials. An item with a colour is one ``MetallicRoughnessMaterial`` of that colour
(``pyrender.Mesh.from_trimesh``, which drops the mesh's visuals). An item without one is drawn in its mesh's
own look (:func:`morphkit.meshes.look.mesh_look`; arrays: :func:`morphkit.meshes.look.look_arrays`) as a
``pyrender.Primitive`` built here, not by ``from_trimesh(material=None)``: its materials are
``alphaMode='BLEND'`` (order-dependent) and single-sided, a trimesh ``SimpleMaterial``'s grey diffuse (0.4)
darkens textures, 16-bit textures wrap in ``astype(uint8)``, greyscale ones crash, and RGB textures of a
width not a multiple of 4 upload skewed (``GL_UNPACK_ALIGNMENT``). Here textures are RGBA uint8
(:func:`morphkit.meshes.texture.texture_rgba`), materials ``OPAQUE``/``MASK``, two-sided. morphkit's copies
of pyrender's fragment shaders (``morphkit/data/shaders``; pyrender's ignore ``alphaMode`` and
``alphaCutoff``) discard fragments with base-colour alpha below 0.5 (a look with cutoff ``c`` uploads its
factor alpha times ``0.5 / c``, an opaque look all alphas at 1: one shader for every cutoff), decode vertex
colours from sRGB before lighting, and draw the normals pass. Items without texture or vertex colours keep
pyrender's own lit shader (their lit pixels are those of earlier versions); every flat draw (the albedo
pass) uses morphkit's ``flat.frag``: the base colour in linear light (factor x decoded texel x decoded
vertex colour), written sRGB-encoded (:mod:`morphkit.conventions`, "Colour"). ``DEPTH_ONLY`` draws ignore
materials (no cut-outs) and always cull back faces (pyrender), dropping an open surface seen from behind
that the two-sided colour draw shows. So a depth image with a cut-out item, or a mesh that is not a
:func:`~morphkit.meshes.closed_volume` (decided once per mesh, by the first depth image showing it), in view
is taken from a flat colour draw (no culling; same vertex transform, so the same depth). Closed volumes keep
``DEPTH_ONLY``: seen from outside, their front faces hide every back face (depth bit-identical). Known
limit: a camera inside a closed volume, or a near plane cutting one, sees back faces that this draw drops.

One-pass frame and G-buffer. :meth:`Renderer.frame_pass` draws a view once into two colour
attachments: the lit colour (:meth:`Renderer.color_depth`'s) and, from the same fragments of morphkit's
``mesh.frag`` (define ``MORPHKIT_FRAME``), the colour with the lights off (ambient, occlusion and emission
alone), an item mark (a uniform per primitive) in its alpha. Closed volumes are drawn single-sided there (as
``DEPTH_ONLY``: the same pixels and known limit, a third less time at 1M faces).
:meth:`Renderer.gbuffer_pass` is :meth:`Renderer.passes` without the lit colour, from one flat draw
(``gbuffer.frag``: ``flat.frag``'s albedo and ``normals.frag``'s encoded normal in two attachments;
two-sided, depth and coverage its own). On OSMesa both draw into a framebuffer object, not OSMesa's buffer:
depth rounds differently (1e-5 relative), a textured pixel may differ by one level.
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
from .conventions import gl_pose_from_cv
from .errors import RenderError, ValidationError, expected_got
from .glplatform import GL_LIBRARIES, check_gl_memory, explain_gl_failure, missing_gl_libraries
from .meshes import closed_volume
from .meshes.look import DIELECTRIC, SurfaceLook, look_arrays, mesh_look
from .passes import (
    FramePass,
    RenderPasses,
    area_passes,
    area_rgba,
    decode_normals,
    linear_depth,
    supersampled_camera,
)
from .scene import AreaLight, DirectionalLight, Item, Light, PointLight
from .settings import EGL_DEVICE, GL_PLATFORM, select_gl_platform
from .validate import as_int

__all__ = ["Renderer", "RenderPasses", "SHADER_DIR", "closed_volume", "gl_info", "missing_gl_libraries",
           "GL_LIBRARIES"]

def _headless_pyglet() -> None:
    """pyglet without its X11 backend (:mod:`morphkit.glplatform`); before pyrender is imported."""
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
_DRAW_RANK: dict[int, int] = {}  # id(node) -> its item's rank in its context's last show: ties' draw order

#: morphkit's copies of pyrender's fragment shaders (package data; module notes, "Materials").
SHADER_DIR = Path(__file__).resolve().parent / "data" / "shaders"
#: Faces above which a mesh is drawn with smooth normals (flat ones would triple a 1M-face mesh).
_SMOOTH_FACES = 20000


if pyrender is not None:
    class _MatrixCamera(pyrender.Camera):
        """A pyrender camera with morphkit's projection matrix (:meth:`CameraModel.gl_projection`):
        pyrender's cannot express every CameraModel (its OrthographicCamera ignores ``xmag``: square
        pixels from the viewport's aspect; off-centre principal points need IntrinsicsCamera)."""

        def __init__(self, projection: np.ndarray, znear: float, zfar: float) -> None:
            super().__init__(znear=znear, zfar=zfar)
            self._P = np.asarray(projection, dtype=np.float64)

        def get_projection_matrix(self, width: int | None = None, height: int | None = None
                                  ) -> np.ndarray:
            return self._P.copy()

    class _ProgramCache(pyrender.shader_program.ShaderProgramCache):
        """pyrender's shader-program cache, keyed without the GL context handle.

        pyrender keys each compiled program by ``OpenGL.contextdata.getContext()``, which under
        OSMesa is a new pointer object on every call: the key never matched, so every colour render
        compiled its programs again and kept the old ones (figures in ``docs/CHANGELOG.md``). Each
        :class:`_Context` has its own renderer and cache, so the context is implicit in the cache.
        """

        #: When set, flat draws use morphkit's normals shader (the normals pass).
        normals: bool = False
        #: When set, draws write two colour attachments: lit ones the unlit colour and the item mark
        #: too (the one-pass frame), flat ones albedo and encoded normals (the G-buffer).
        frame: bool = False

        def _path(self, name: str | None, defines: dict) -> str | None:
            """The file of shader ``name``: morphkit's copy for every flat draw (albedo, normals,
            G-buffer), lit textured or vertex-coloured primitives and one-pass frames, else pyrender's."""
            if name is None:
                return None
            if name == "flat.frag":
                return str(SHADER_DIR / ("gbuffer.frag" if self.frame else
                                         "normals.frag" if self.normals else "flat.frag"))
            if name == "mesh.frag" and {"HAS_BASE_COLOR_TEX", "COLOR_0_LOC", "MORPHKIT_FRAME"} & set(defines):
                return str(SHADER_DIR / name)
            return os.path.join(self.shader_dir, name)

        def get_program(self, vertex_shader: str, fragment_shader: str, geometry_shader: str | None = None,
                        defines: dict | None = None) -> pyrender.shader_program.ShaderProgram:
            defines = {} if defines is None else defines
            if self.frame and fragment_shader == "mesh.frag":
                defines = {**defines, "MORPHKIT_FRAME": 1}
            vs, fs, gs = (self._path(f, defines) for f in (vertex_shader, fragment_shader, geometry_shader))
            key = (vs, fs, gs, tuple(sorted(defines.items())))
            program = self._program_cache.get(key)
            if program is None:
                program = self._program_cache[key] = pyrender.shader_program.ShaderProgram(
                    vertex_shader=vs, fragment_shader=fs, geometry_shader=gs, defines=defines)
            return program

    class _SingleSampleRenderer(pyrender.Renderer):
        """pyrender's renderer with single-sampled offscreen buffers (EGL's framebuffer path).

        pyrender allocates its "multisample" colour and depth buffers with 4 samples and blits
        them into single-sampled ones (depth read back off the pixel centre). Here they are
        re-allocated with 0 samples right after pyrender creates them: the blit is an exact copy.
        Programs are cached per context (``_ProgramCache``). :meth:`two_pass` draws into a second
        colour attachment too (the unlit colour and the item marks, or the encoded normals). Ties in
        distance draw in the items' order, not pyrender's set order (which varies between runs)."""

        def __init__(self, width: int, height: int) -> None:
            self._unlit_rb: Any = None  # the second colour attachment, made by the first two_pass
            self._frame: tuple[dict[int, float], set[int]] | None = None  # marks, cull: in a two_pass
            super().__init__(width, height)
            self._program_cache = _ProgramCache()
            self._single_sampled: tuple[Any, Any] | None = None

        def _sorted_mesh_nodes(self, scene: pyrender.Scene) -> list[pyrender.Node]:
            at = scene.get_pose(scene.main_camera_node)[:3, 3]
            return sorted(scene.mesh_nodes, key=lambda n: (n.mesh.is_transparent, -float(
                np.linalg.norm(scene.get_pose(n)[:3, 3] - at)), _DRAW_RANK.get(id(n), 0)))

        def _delete_main_framebuffer(self) -> None:
            if self._unlit_rb is not None:
                _GL.glDeleteRenderbuffers(1, [self._unlit_rb])
                self._unlit_rb = None
            super()._delete_main_framebuffer()

        def _configure_forward_pass_viewport(self, flags: int) -> None:
            super()._configure_forward_pass_viewport(flags)  # binds the main framebuffer offscreen
            if self._frame is not None and self._unlit_rb is None:
                self._unlit_rb = _GL.glGenRenderbuffers(1)
                _GL.glBindRenderbuffer(_GL.GL_RENDERBUFFER, self._unlit_rb)
                _GL.glRenderbufferStorage(_GL.GL_RENDERBUFFER, _GL.GL_RGBA8, *self._main_fb_dims)
                _GL.glFramebufferRenderbuffer(_GL.GL_DRAW_FRAMEBUFFER, _GL.GL_COLOR_ATTACHMENT1,
                                              _GL.GL_RENDERBUFFER, self._unlit_rb)
            if flags & pyrender.RenderFlags.OFFSCREEN:
                n = 1 if self._frame is None else 2
                _GL.glDrawBuffers(n, [_GL.GL_COLOR_ATTACHMENT0, _GL.GL_COLOR_ATTACHMENT1][:n])

        def _bind_and_draw_primitive(self, primitive: Any, pose: Any, program: Any, flags: int) -> None:
            """pyrender's, and in a :meth:`two_pass` the item mark and single-sided closed volumes."""
            material, two_sided = primitive.material, primitive.material.doubleSided
            if self._frame is not None:
                program.set_uniform("item_mark", self._frame[0].get(id(primitive), 0.0))
                material.doubleSided = two_sided and id(primitive) not in self._frame[1]
            try:
                super()._bind_and_draw_primitive(primitive, pose, program, flags)
            finally:
                material.doubleSided = two_sided

        def two_pass(self, scene: pyrender.Scene, flags: int, marks: dict[int, float], cull: set[int]
                     ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
            """One draw of ``scene`` offscreen (the context current) into both attachments, lit (lit and
            unlit RGBA, the mark in the unlit alpha) or ``FLAT`` (albedo, encoded normals), and pyrender's
            depth; ``cull``: single-sided primitives."""
            self._frame, self._program_cache.frame = (marks, cull), True
            try:
                (first, second), depth = self.render(scene, flags | pyrender.RenderFlags.OFFSCREEN)
            finally:
                self._frame, self._program_cache.frame = None, False
            return cv2.flip(first, 0), depth, cv2.flip(second, 0)  # colours: bottom row read first

        def _read_main_framebuffer(self, scene: pyrender.Scene, flags: int) -> Any:
            """pyrender's; in a :meth:`two_pass` both colours, read where drawn (single-sampled: no
            blit) as RGBA (no conversion), and depth by pyrender's formula without its masking."""
            if self._frame is None:
                return super()._read_main_framebuffer(scene, flags)
            (w, h), gl = self._main_fb_dims, _GL
            gl.glBindFramebuffer(gl.GL_READ_FRAMEBUFFER, self._main_fb_ms)
            rgba = []
            for att in (gl.GL_COLOR_ATTACHMENT1, gl.GL_COLOR_ATTACHMENT0):  # unlit, lit (pyrender's setting)
                gl.glReadBuffer(att)
                rgba.insert(0, gl.glReadPixels(0, 0, w, h, gl.GL_RGBA, gl.GL_UNSIGNED_BYTE))
            z = np.frombuffer(gl.glReadPixels(0, 0, w, h, gl.GL_DEPTH_COMPONENT, gl.GL_FLOAT), np.float32)
            n, f = scene.main_camera_node.camera.znear, scene.main_camera_node.camera.zfar
            lin = np.where(z == 1.0, np.float32(0.0), 2.0 * n * f / (f + n - (2.0 * z - 1.0) * (f - n)))
            return [np.frombuffer(b, np.uint8).reshape(h, w, 4) for b in rgba], lin.reshape(h, w)[::-1]

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
        """pyrender's offscreen renderer on :data:`~morphkit.settings.GL_PLATFORM`, with the corrected
        EGL platform and renderer (module notes) and per-context shader cache (``_ProgramCache``)."""

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

        def two_pass(self, scene: pyrender.Scene, flags: int, marks: dict[int, float], cull: set[int]
                     ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
            """:meth:`_SingleSampleRenderer.two_pass` with this context current."""
            self._platform.make_current()
            try:
                return self._renderer.two_pass(scene, flags, marks, cull)
            finally:
                self._platform.make_uncurrent()

    def _flat_color_mesh(mesh: trimesh.Trimesh, color: tuple[float, ...]) -> pyrender.Mesh:
        """One colour: pyrender's ``from_trimesh`` with one material (drops the mesh's visuals)."""
        mat = pyrender.MetallicRoughnessMaterial(
            baseColorFactor=[*color, 1.0], metallicFactor=DIELECTRIC[0], roughnessFactor=DIELECTRIC[1],
            doubleSided=True)
        # Flat shading for small meshes (boxes look right); smooth for large ones (_SMOOTH_FACES)
        return pyrender.Mesh.from_trimesh(mesh, material=mat, smooth=len(mesh.faces) > _SMOOTH_FACES)

    def _look_mesh(mesh: trimesh.Trimesh, look: SurfaceLook) -> pyrender.Mesh:
        """A mesh's own look as one primitive (module notes, "Materials")."""
        a = look_arrays(mesh, look, smooth=len(mesh.faces) > _SMOOTH_FACES and look.face_colors is None)
        tex = None if a["texture"] is None else pyrender.Texture(
            source=a["texture"], source_channels="RGBA", sampler=pyrender.Sampler())
        mat = pyrender.MetallicRoughnessMaterial(
            baseColorFactor=a["factor"], baseColorTexture=tex, metallicFactor=look.metallic,
            roughnessFactor=look.roughness, doubleSided=True,
            alphaMode="MASK" if look.masked else "OPAQUE", alphaCutoff=look.alpha_cutoff)
        prim = pyrender.Primitive(positions=a["positions"], normals=a["normals"], texcoord_0=a["uv"],
                                  color_0=a["colors"], indices=a["indices"], material=mat,
                                  mode=pyrender.constants.GLTF.TRIANGLES)
        return pyrender.Mesh(primitives=[prim])


def gl_info(*, open_context: bool = True) -> dict[str, str | None]:
    """The GL platform and the renderer string in use (the benches write both into their JSON rows):
    ``GL_RENDERER``, ``GL_VERSION`` and ``GL_VENDOR`` of this process's first context (or of a small
    one made and closed to read them, unless ``open_context`` is False).

    Parameters
    ----------
    open_context : bool, optional
        Create a context to read the strings when this process has none yet (default True).

    Returns
    -------
    dict of str to str or None
        ``platform`` (``"osmesa"`` or ``"egl"``), ``renderer`` (``"llvmpipe (LLVM ...)"`` or the GPU's),
        ``version``, ``vendor``; the GL strings are None where no context was read (``error``: why).
    """
    info: dict[str, str | None] = {"platform": GL_PLATFORM}
    if not _GL_STRINGS and open_context:
        try:
            if pyrender is None:
                raise RenderError(explain_gl_failure(_IMPORT_ERROR or RuntimeError("pyrender not imported")))
            _Offscreen(8, 8).delete()
        except Exception as exc:  # noqa: BLE001 - reported, not raised: a bench row still gets written
            return {**info, "renderer": None, "version": None, "vendor": None, "error": repr(exc)}
    return {**info, **(_GL_STRINGS or {"renderer": None, "version": None, "vendor": None})}


class _Context:
    """One GL context of a fixed shape with its scene and node cache.

    Each (mesh, look) is converted and uploaded once (one ``pyrender.Mesh``; the look is the item's
    colour, or the mesh's own look for ``color=None``); several :class:`~morphkit.scene.Item` s
    sharing it (instances of one mesh at several poses) get one node each, all referring to that
    uploaded mesh."""

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
        self.pools: dict[int, list[pyrender.Node]] = {}  # id(pool) -> pool
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
            self.pools[id(pool)] = pool
            if item.color is None and look.masked:
                self.flat_depth[id(pool)] = True
        return pool

    def show(self, items: Sequence[Item]) -> None:
        groups: dict[int, tuple[list[pyrender.Node], list[tuple[int, Item]]]] = {}
        for rank, it in enumerate(items):
            pool = self._pool(it)
            groups.setdefault(id(pool), (pool, []))[1].append((rank, it))
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
                        self.scene.set_pose(node, np.asarray(used[k][1].pose, dtype=np.float64))
                        _DRAW_RANK[id(node)] = used[k][0]
                    elif k > 0 and self.scene.has_node(node):
                        self.scene.remove_node(node)

    def depth_needs_flat_draw(self) -> bool:
        """Whether an upload shown has cut-outs or is not a closed volume (decided once each)."""
        for k in self.shown:
            if k not in self.flat_depth:
                self.flat_depth[k] = not closed_volume(self.pool_mesh[k])
        return any(self.flat_depth[k] for k in self.shown)

    def frame_ids(self, marked: Iterable[Item]) -> tuple[dict[int, float], set[int]]:
        """``id`` of the primitives of ``marked`` (mark 1), and of the closed volumes shown without
        cut-outs (drawn single-sided; decided once each)."""
        self.depth_needs_flat_draw()
        closed = [self.pools[k] for k in self.shown if not self.flat_depth[k]]
        return ({id(p): 1.0 for it in marked for p in self._pool(it)[0].mesh.primitives},
                {id(p) for pool in closed for p in pool[0].mesh.primitives})

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
        return [pl for p in light.point_lights(2) for pl in _as_pyrender_lights(p)]
    raise ValidationError(expected_got("light", "a DirectionalLight, PointLight or AreaLight",
                                       type(light).__name__))


class Renderer:
    """A reusable headless renderer (create once, render many frames).

    Creating a GL context costs far more than rendering a frame in it (``morphkit bench render``).
    Keep one :class:`Renderer` for a whole session; it keeps one context per image shape. Call
    :meth:`close` (or use ``with``) to free GL."""

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
        if camera.shape not in self._contexts:
            self._contexts[camera.shape] = _Context(camera.shape)
        return self._contexts[camera.shape]

    def _shown(self, camera: CameraModel, items: Sequence[Item]) -> _Context:
        """The context of ``camera`` showing ``items`` (checked)."""
        for it in items:
            if not isinstance(it, Item):
                raise ValidationError(expected_got("items", "a sequence of morphkit.render.Item",
                                                   type(it).__name__))
        ctx = self._ctx(camera)
        ctx.show(items)
        return ctx

    def _lit(self, camera: CameraModel, items: Sequence[Item], lights: Iterable[Light], ambient: float,
             background: tuple[float, float, float]) -> _Context:
        """The context of ``camera`` set up for a lit draw of ``items``."""
        ctx = self._shown(camera, items)
        ctx.set_camera(camera)
        ctx.set_lights(lights, ambient)
        ctx.scene.bg_color = np.array([*background, 0.0])
        return ctx

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
        ctx = self._shown(camera, items)
        ctx.set_camera(camera)
        return ctx.renderer.render(ctx.scene, flags=pyrender.RenderFlags.DEPTH_ONLY)

    def depth(self, camera: CameraModel, items: Sequence[Item]) -> np.ndarray:
        """Linear depth ``(H, W)`` float32 of ``items`` seen by ``camera``; background ``+inf``.

        Cut-out texels are holes, and every surface is two-sided as in the colour draw (module
        notes, "Materials").

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
        ctx = self._shown(camera, items)
        if ctx.depth_needs_flat_draw():
            return linear_depth(self._flat(ctx, camera, normals=False)[1], camera)
        return linear_depth(self.pyrender_depth(camera, items), camera)

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
        return self._flat(self._shown(camera, items), camera, normals=False)[0]

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
        enc, raw = self._flat(self._shown(camera, items), camera, normals=True)
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
        albedo, enc = (self._flat(self._ctx(camera), camera, normals=n)[0] for n in (False, True))
        covered = np.isfinite(depth)
        return RenderPasses(color, albedo, decode_normals(enc, covered), depth, covered.astype(np.float32))

    def gbuffer_pass(self, camera: CameraModel, items: Sequence[Item]) -> RenderPasses:
        """:meth:`passes` without its lit colour, from one draw (module notes, "One-pass frame and G-buffer").

        Parameters
        ----------
        camera : CameraModel
            The view.
        items : sequence of Item
            Items to draw, world poses.

        Returns
        -------
        RenderPasses
            As :meth:`passes`' (``alpha`` 0 or 1), but ``color`` is ``albedo``: no lit colour is drawn.
        """
        check_gl_memory(camera.shape, tol.GL_FRAME_PASS_BYTES_PER_PIXEL)  # its framebuffers (once made)
        ctx = self._lit(camera, items, (), 0.0, (0.0, 0.0, 0.0))  # no light in a flat draw
        rgba, raw, code = ctx.renderer.two_pass(ctx.scene, pyrender.RenderFlags.FLAT, {}, set())
        depth, albedo = linear_depth(raw, camera), cv2.cvtColor(rgba, cv2.COLOR_RGBA2RGB)
        covered = np.isfinite(depth)
        return RenderPasses(albedo, albedo, decode_normals(code[..., :3], covered), depth,
                            covered.astype(np.float32))

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
        return area_passes(self.passes(supersampled_camera(camera, s), items, lights, ambient=ambient),
                           camera.shape)

    def color_depth(self, camera: CameraModel, items: Sequence[Item], lights: Iterable[Light],
                    *, ambient: float = 0.35,
                    background: tuple[float, float, float] = (0.0, 0.0, 0.0),
                    ) -> tuple[np.ndarray, np.ndarray]:
        """Shaded colour ``(H, W, 3)`` uint8 and linear depth ``(H, W)`` float32.

        No shadows are drawn (shadows are morphkit's job).

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
        ctx = self._lit(camera, items, lights, ambient, background)
        color, raw = ctx.renderer.render(ctx.scene, flags=pyrender.RenderFlags.NONE)
        return np.ascontiguousarray(color[..., :3]), linear_depth(raw, camera)

    def frame_pass(self, camera: CameraModel, items: Sequence[Item], lights: Iterable[Light], *,
                   ambient: float = 0.35, background: tuple[float, float, float] = (0.0, 0.0, 0.0),
                   marked: Sequence[int] = ()) -> FramePass:
        """Lit and unlit :meth:`color_depth` from one draw, and ``marked`` items' pixels (module notes).

        Parameters
        ----------
        camera : CameraModel
            The view.
        items : sequence of Item
            Items to draw, world poses.
        lights : iterable of Light
            Lights, world frame (on in ``lit``, off in ``unlit``).
        ambient : float, optional
            Ambient light level.
        background : tuple of 3 float, optional
            RGB in ``[0, 1]`` where nothing is drawn (in both colours).
        marked : sequence of int, optional
            Indices into ``items`` of the items whose visible pixels ``marked`` shows.

        Returns
        -------
        FramePass
            ``lit``, ``unlit``, ``depth`` and ``marked``.
        """
        check_gl_memory(camera.shape, tol.GL_FRAME_PASS_BYTES_PER_PIXEL)  # its framebuffers (once made)
        ctx = self._lit(camera, items, lights, ambient, background)
        ids = ctx.frame_ids([items[as_int(k, "marked index", lo=0, hi=len(items) - 1)] for k in marked])
        color, raw, unlit = ctx.renderer.two_pass(ctx.scene, pyrender.RenderFlags.NONE, *ids)
        return FramePass(cv2.cvtColor(color, cv2.COLOR_RGBA2RGB), cv2.cvtColor(unlit, cv2.COLOR_RGBA2RGB),
                         linear_depth(raw, camera), unlit[..., 3] >= 128)

    def source_view(self, camera: CameraModel, items: Sequence[Item], lights: Iterable[Light], *,
                    ambient: float = 0.35, supersample: int = 3) -> np.ndarray:
        """RGBA ``(H, W, 4)`` uint8 of ``items`` alone on a transparent background.

        Alpha is pixel coverage (drawn at ``supersample`` times the resolution and area-averaged:
        OSMesa has no multisampling); colour is straight (un-premultiplied) alpha.

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
        s = as_int(supersample, "supersample", lo=1)
        color, depth = self.color_depth(supersampled_camera(camera, s), items, lights, ambient=ambient)
        return area_rgba(color, depth, camera.shape)
