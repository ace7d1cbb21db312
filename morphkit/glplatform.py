"""What a GL context needs from the machine (its libraries, its memory), and what to say when
it is missing.

No GL is imported here (ctypes only), so the message for a machine without GL can be built
before, and without, pyrender: :mod:`morphkit.render` uses it when pyrender cannot be
imported or a context cannot be created, and calls :func:`check_gl_memory` before it
creates one. The platform itself is chosen in :mod:`morphkit.settings` (``MORPHKIT_GL``).

Platform. :data:`morphkit.settings.GL_PLATFORM` picks the GL platform once per process:
``osmesa`` (default; software, any Linux machine with ``libosmesa6``) or ``egl``
(``MORPHKIT_GL=egl``: a GPU through its driver's EGL, or Mesa's software EGL where there is
none). ``PYOPENGL_PLATFORM`` is set from it before pyrender (and PyOpenGL) are imported.

Headless import. pyrender imports its pyglet viewer, whose X11 backend (``libX11``, ``libXrender``)
fails without X11 client libraries; morphkit never opens a window: :mod:`morphkit.render` sets
pyglet's ``headless`` option before it imports pyrender (pyglet then loads ``libEGL`` and ``libGL``
only). A failed import names the GL library that could not be loaded and its package
(:func:`missing_gl_libraries`).
"""

from __future__ import annotations

import ctypes
import ctypes.util

import numpy as np

from . import tol
from .errors import RenderError, expected_got
from .settings import GL_PLATFORM

__all__ = ["GL_LIBRARIES", "missing_gl_libraries", "explain_gl_failure", "check_gl_memory"]

#: Shared libraries each platform loads (library name as ``ctypes.util.find_library`` takes it,
#: what provides it on Debian/Ubuntu). pyglet's headless mode (imported with pyrender) loads
#: EGL and GL on either platform.
GL_LIBRARIES: dict[str, tuple[tuple[str, str], ...]] = {
    "osmesa": (("OSMesa", "libosmesa6"), ("EGL", "libegl1 libegl-mesa0"), ("GL", "libgl1")),
    "egl": (("EGL", "libegl1 libegl-mesa0 (or the GPU driver's EGL)"), ("OpenGL", "libopengl0"),
            ("GL", "libgl1")),
}


def missing_gl_libraries(platform: str = GL_PLATFORM) -> list[tuple[str, str]]:
    """The GL libraries of ``platform`` this process cannot load, with their packages.

    Parameters
    ----------
    platform : str, optional
        ``"osmesa"`` or ``"egl"`` (default: this process's platform).

    Returns
    -------
    list of (str, str)
        ``(library, package)`` for each library of :data:`GL_LIBRARIES` that fails to load,
        e.g. ``("EGL", "libegl1 libegl-mesa0")``; empty when all load.
    """
    missing = []
    for lib, package in GL_LIBRARIES.get(platform, ()):
        try:
            ctypes.CDLL(ctypes.util.find_library(lib) or f"lib{lib}.so")
        except OSError:
            missing.append((lib, package))
    return missing


def explain_gl_failure(exc: BaseException) -> str:
    """Why pyrender could not be imported (or a context not created), with the fix.

    Parameters
    ----------
    exc : BaseException
        The error pyrender or the GL platform raised.

    Returns
    -------
    str
        The message: the GL libraries that cannot be loaded and the packages that provide
        them, or the original error with the platform setting when every library loads.
    """
    missing = missing_gl_libraries()
    if missing:
        libs = ", ".join(f"lib{lib}" for lib, _ in missing)
        pkgs = " ".join(p.split(" (")[0] for _, p in missing)
        return (f"the GL platform {GL_PLATFORM!r} needs {libs}, which cannot be loaded "
                f"(install it: apt-get install {pkgs}; or run scripts/setup.sh as root). "
                f"Original error: {exc!r}")
    return (f"{exc!r} (GL platform {GL_PLATFORM!r}: MORPHKIT_GL selects osmesa or egl; "
            "morphkit needs PyOpenGL >= 3.1.9)")


def check_gl_memory(shape: tuple[int, int], bytes_per_pixel: int = tol.GL_BYTES_PER_PIXEL) -> None:
    """Refuse a GL context of ``shape`` that this process has no memory for, before GL allocates.

    Mesa (llvmpipe) does not survive a failed allocation of its framebuffers or tiles: it
    dereferences the null pointer and the process dies of a segfault (a 8192 x 8192 demo under a
    2 GiB address-space limit). So the memory a context and its first draw take
    (:data:`morphkit.tol.GL_BYTES_PER_PIXEL` per pixel) is allocated and released here first,
    untouched (address space only): where the process cannot get it (``RLIMIT_AS``, or more
    than the machine has), a :class:`~morphkit.errors.RenderError` instead.

    Parameters
    ----------
    shape : (int, int)
        The context's image shape ``(H, W)``.
    bytes_per_pixel : int, optional
        What it takes per pixel (a new context's default; the one-pass frame's framebuffers:
        :data:`morphkit.tol.GL_FRAME_PASS_BYTES_PER_PIXEL`).

    Raises
    ------
    RenderError
        The memory cannot be allocated.
    """
    need = int(bytes_per_pixel) * int(shape[0]) * int(shape[1])
    try:
        np.empty(need, np.uint8)
    except MemoryError:
        raise RenderError(expected_got(
            f"memory for an offscreen GL context of shape {tuple(shape)}",
            f"about {need / 2**20:.0f} MiB (its framebuffers and draws)",
            "a MemoryError: more than this process may allocate (its memory limit or the machine's "
            "memory); render smaller images")) from None
