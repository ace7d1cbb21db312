"""The GL libraries each rendering platform needs, and what to say when one is missing.

No GL is imported here (ctypes only), so the message for a machine without GL can be built
before, and without, pyrender: :mod:`morphkit.render` uses it when pyrender cannot be
imported or a context cannot be created. The platform itself is chosen in
:mod:`morphkit.settings` (``MORPHKIT_GL``).
"""

from __future__ import annotations

import ctypes
import ctypes.util

from .settings import GL_PLATFORM

__all__ = ["GL_LIBRARIES", "missing_gl_libraries", "explain_gl_failure"]

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
