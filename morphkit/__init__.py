"""morphkit: shadows and view-dependent billboards by warping images.

Conventions (pixels, frames, depth) are stated once in :mod:`morphkit.conventions`.
The pyrender/OpenGL boundary is :mod:`morphkit.render`; nothing else imports pyrender,
so the numpy/OpenCV core works without a GL context.
"""

from __future__ import annotations

from .errors import (
    ClusterError,
    DegenerateViewError,
    FileFormatError,
    FoldOverError,
    GeometryError,
    MeshError,
    MorphkitError,
    OutOfRangeError,
    OutputBusyError,
    OutputExistsError,
    OutputWriteError,
    RenderError,
    UsageError,
    ValidationError,
)

#: The package version (as in ``pyproject.toml``).
__version__ = "0.1.0"

__all__ = [
    "__version__",
    "MorphkitError",
    "ValidationError",
    "MeshError",
    "OutOfRangeError",
    "GeometryError",
    "FoldOverError",
    "DegenerateViewError",
    "RenderError",
    "FileFormatError",
    "ClusterError",
    "OutputExistsError",
    "OutputBusyError",
    "OutputWriteError",
    "UsageError",
]
