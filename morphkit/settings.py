"""Run-time settings, read once from the environment when morphkit is imported.

Every environment switch morphkit honours is read here and nowhere else; other
modules import the resulting constants.

=========================  ==================================================
variable                   effect
=========================  ==================================================
``MORPHKIT_WARP_NUMPY=1``  every compiled kernel (warp maps, fused warps, shadow
                           lookup, fold relaxation, reprojection) runs its numpy
                           reference instead (:data:`COMPILED` is False); the
                           tests compare the two paths.
``MORPHKIT_WARP_THREADS``  threads of the banded warp and reprojection passes
                           (:data:`WARP_THREADS`; default: CPUs, at most 4).
``OMP_WAIT_POLICY``        defaults to ``PASSIVE`` (see below); a value you set wins.
``MORPHKIT_GL``            the GL platform (:data:`GL_PLATFORM`): ``osmesa``
                           (default: software, any Linux machine) or ``egl``
                           (a GPU through its driver's EGL, or Mesa's software
                           EGL); read once, fixed for the process.
``PYOPENGL_PLATFORM``      used as ``MORPHKIT_GL`` when that is unset;
                           :func:`select_gl_platform` sets it to
                           :data:`GL_PLATFORM` for PyOpenGL.
``MORPHKIT_EGL_DEVICE``    EGL device index (:data:`EGL_DEVICE`, default
                           ``EGL_DEVICE_ID`` or 0: the first GPU).
``MORPHKIT_ASSET_ROOT``    the folder the files a mesh refers to (materials,
                           textures, buffers) may lie in (:data:`ASSET_ROOT`;
                           default: each mesh file's own folder;
                           :mod:`morphkit.meshes.assets`).
``MORPHKIT_CACHE``         where morphkit keeps what it measures once per asset and
                           reuses (:data:`CACHE_DIR`: a plan's error tables; default
                           ``$XDG_CACHE_HOME/morphkit``, else ``~/.cache/morphkit``).
``NUMBA_CACHE_DIR``        where numba caches compiled kernels on disk (numba
                           reads it; default ``__pycache__`` beside the module).
=========================  ==================================================

A value a variable does not take (``MORPHKIT_WARP_THREADS=abc``) is refused with a
:class:`~morphkit.errors.ValidationError` that names it, when this module is imported;
:func:`check_environment` checks them again (and ``MORPHKIT_GL``) for the command line.

Compiled kernels
----------------
:func:`compile_kernel` is the one gate between numba and numpy: it returns the
jitted function, or ``None`` when numba cannot be imported. A caller keeps its
numpy reference and runs the kernel only when :func:`use_compiled` says so.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from typing import Any, TypeVar

from . import tol
from .errors import ValidationError, expected_got

# numba's parallel bands run on OpenMP (libgomp) where available, whose idle
# threads spin-wait by default and take the cores from the cv2.remap that
# follows every fill.
# Passive waiting keeps the cores free for OpenCV; set before libgomp loads, and
# a value the user set wins.
os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")

try:  # optional at import time: every kernel has a numpy reference
    import numba
except ImportError:  # pragma: no cover - numba is a dependency
    numba = None

__all__ = ["numba", "NUMBA_AVAILABLE", "NUMPY_ONLY", "COMPILED", "WARP_THREADS", "compile_kernel",
           "use_compiled", "select_gl_platform", "check_environment", "GL_PLATFORMS", "GL_PLATFORM",
           "EGL_DEVICE", "ASSET_ROOT", "CACHE_DIR", "child_environment"]

F = TypeVar("F", bound=Callable[..., Any])

#: numba could be imported.
NUMBA_AVAILABLE: bool = numba is not None

#: ``MORPHKIT_WARP_NUMPY=1`` forces the numpy reference path of every compiled kernel.
NUMPY_ONLY: bool = bool(os.environ.get("MORPHKIT_WARP_NUMPY"))

#: Compiled kernels run (numba is there and ``MORPHKIT_WARP_NUMPY`` is unset).
COMPILED: bool = NUMBA_AVAILABLE and not NUMPY_ONLY


def _default_threads() -> int:
    n = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)
    return min(4, n)


#: ``MORPHKIT_ASSET_ROOT``: the folder a mesh's materials, textures and buffers may lie in
#: (:mod:`morphkit.meshes.assets`); None (unset): each mesh file's own folder.
ASSET_ROOT: str | None = os.environ.get("MORPHKIT_ASSET_ROOT") or None

#: The folder of morphkit's per-asset measurements kept between runs (``MORPHKIT_CACHE``; default
#: ``$XDG_CACHE_HOME/morphkit`` or ``~/.cache/morphkit``); created when first written.
CACHE_DIR: str = os.environ.get("MORPHKIT_CACHE") or os.path.join(
    os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache"), "morphkit")


def _env_int(names: tuple[str, ...], lo: int, hi: int, what: str) -> int | None:
    """The first of the variables ``names`` that is set (and not blank) as an integer in
    ``[lo, hi]``, or None when none is set.

    Raises
    ------
    ValidationError
        The variable's value is not such an integer (named, with what it takes).
    """
    for name in names:
        raw = os.environ.get(name)
        if raw is None or not raw.strip():
            continue
        try:
            value = int(raw.strip())
        except ValueError:
            value = None
        if value is None or not lo <= value <= hi:
            raise ValidationError(expected_got(f"environment variable {name}", f"an integer in [{lo}, {hi}] "
                                               f"({what}; or unset)", repr(raw)))
        return value
    return None


def _warp_threads() -> int:
    return _env_int(("MORPHKIT_WARP_THREADS",), 1, tol.MAX_WARP_THREADS,
                    "threads of the banded passes, tol.MAX_WARP_THREADS") or _default_threads()


def _egl_device() -> int:
    return _env_int(("MORPHKIT_EGL_DEVICE", "EGL_DEVICE_ID"), 0, tol.MAX_EGL_DEVICE,
                    "an EGL device index, tol.MAX_EGL_DEVICE") or 0


#: Threads that share a banded pass (fused warp accumulation, reprojection), each
#: taking a band of rows: one per CPU this process may use, at most 4;
#: ``MORPHKIT_WARP_THREADS`` overrides (an integer in ``[1, tol.MAX_WARP_THREADS]``;
#: anything else is refused when morphkit.settings is imported).
WARP_THREADS: int = _warp_threads()


def compile_kernel(fn: F, **options: Any) -> F | None:
    """``numba.njit(cache=True, nogil=True, **options)(fn)``, or None without numba.

    Compiled even under ``MORPHKIT_WARP_NUMPY=1`` (tests compare the two
    paths); callers decide with :func:`use_compiled`.

    Parameters
    ----------
    fn : callable
        The pure-Python kernel.
    **options : Any
        Further ``numba.njit`` options (e.g. ``parallel=True``).

    Returns
    -------
    callable or None
        The compiled kernel, or None when numba is not installed.
    """
    if numba is None:
        return None
    return numba.njit(cache=True, nogil=True, **options)(fn)


def use_compiled(kernel: Callable[..., Any] | None) -> bool:
    """True when ``kernel`` (from :func:`compile_kernel`) exists and compiled kernels are enabled.

    Parameters
    ----------
    kernel : callable or None
        A kernel from :func:`compile_kernel`.

    Returns
    -------
    bool
        Whether to call the compiled kernel rather than the numpy path.
    """
    return kernel is not None and not NUMPY_ONLY


#: The GL platforms :mod:`morphkit.render` can use.
GL_PLATFORMS: tuple[str, ...] = ("osmesa", "egl")

#: The GL platform of this process: ``MORPHKIT_GL``, else ``PYOPENGL_PLATFORM``, else
#: ``"osmesa"`` (lower-cased; anything outside :data:`GL_PLATFORMS` is refused when
#: :mod:`morphkit.render` is imported, by :func:`select_gl_platform`).
GL_PLATFORM: str = (os.environ.get("MORPHKIT_GL") or os.environ.get("PYOPENGL_PLATFORM")
                    or "osmesa").strip().lower()

#: EGL device index (``MORPHKIT_EGL_DEVICE``, else pyrender's ``EGL_DEVICE_ID``, else 0).
EGL_DEVICE: int = _egl_device()


def select_gl_platform() -> str:
    """Tell PyOpenGL the platform (``PYOPENGL_PLATFORM`` = :data:`GL_PLATFORM`); return it.

    Must run before the first OpenGL import (:mod:`morphkit.render` calls it).

    Returns
    -------
    str
        :data:`GL_PLATFORM`, now in ``PYOPENGL_PLATFORM``.

    Raises
    ------
    ValidationError
        :data:`GL_PLATFORM` is not one of :data:`GL_PLATFORMS`.
    """
    if GL_PLATFORM not in GL_PLATFORMS:
        raise ValidationError(expected_got("MORPHKIT_GL (or PYOPENGL_PLATFORM)",
                                           f"one of {', '.join(GL_PLATFORMS)}", repr(GL_PLATFORM)))
    os.environ["PYOPENGL_PLATFORM"] = GL_PLATFORM
    return GL_PLATFORM


def check_environment() -> None:
    """Refuse, as this process's environment now reads, a morphkit variable whose value is not one it
    takes: ``MORPHKIT_WARP_THREADS``, ``MORPHKIT_EGL_DEVICE`` (or ``EGL_DEVICE_ID``) and
    ``MORPHKIT_GL`` (the command line calls it first, before ``--help``).

    Raises
    ------
    ValidationError
        The first such variable, its value and what it takes.
    """
    _warp_threads()
    _egl_device()
    gl = os.environ.get("MORPHKIT_GL")
    if gl is not None and gl.strip() and gl.strip().lower() not in GL_PLATFORMS:
        raise ValidationError(expected_got("environment variable MORPHKIT_GL",
                                           f"one of {', '.join(GL_PLATFORMS)} (or unset)", repr(gl)))


def child_environment(**overrides: str) -> dict[str, str]:
    """This process's environment with ``overrides``, for a child process (e.g. a fresh numba cache).

    Parameters
    ----------
    **overrides : str
        Variables to set in the child, e.g. ``NUMBA_CACHE_DIR="/tmp/x"``.

    Returns
    -------
    dict of str to str
        A copy of ``os.environ`` updated with ``overrides``.
    """
    return {**os.environ, **overrides}
