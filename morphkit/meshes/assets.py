"""The files a mesh file refers to: one resolver for materials, textures and buffers.

An OBJ names its material libraries (``mtllib``) and their images (``map_Kd``); a
``.gltf`` names its buffers and images by URI. Every such file is found by
:func:`locate` and read by :class:`AssetResolver` (the resolver :func:`load_mesh
<morphkit.meshes.load_mesh>` passes to ``trimesh.load``), and by nothing else:

* **confined**: a reference is looked up inside the *asset root* only, by default the
  mesh file's own folder. One that lies outside it (``../outside.mtl``,
  ``/etc/shadow``, a link out of the folder) is never opened: the mesh loads without
  it, with one :class:`~morphkit.errors.AssetWarning` naming it. A pack that keeps its
  textures beside the mesh folder (``../textures/``) widens the root explicitly:
  ``load_mesh(path, asset_root=...)`` or ``MORPHKIT_ASSET_ROOT``
  (:data:`morphkit.settings.ASSET_ROOT`); the mesh file must lie inside the root.
* **regular files only**: a reference to a FIFO, a device or a socket (which would block
  the read, or never end) is a :class:`~morphkit.errors.MeshError` before anything is read.
* **images checked**: an image file the loader checked (:meth:`AssetResolver.check_image`:
  read and decoded before the load) is served from what was read then; one that cannot be
  read or decoded is withheld, as if missing (the loader warns and draws the material without
  it).

trimesh's own ``FilePathResolver`` (since trimesh 5.0) confines paths to the file's folder
too, but opens whatever is there (a FIFO blocks it) and has no root wider than the folder
other than "anywhere"; trimesh also swallows a resolver's errors for materials and images,
so :class:`AssetResolver` records what it refused for :func:`load_mesh
<morphkit.meshes.load_mesh>` to report after the load.
"""

from __future__ import annotations

import os
import stat
from pathlib import Path
from urllib.parse import unquote

from trimesh.resolvers import FilePathResolver

from ..errors import MeshError, expected_got
from ..files.fileio import file_kind
from .texture import image_problem

__all__ = ["AssetResolver", "asset_root", "locate", "read_regular"]


def asset_root(mesh_path: str | os.PathLike[str], root: str | os.PathLike[str] | None = None) -> Path:
    """The folder the files ``mesh_path`` refers to must lie in: ``root``, or the mesh's folder.

    Parameters
    ----------
    mesh_path : str or os.PathLike
        The mesh file.
    root : str or os.PathLike, optional
        A wider root chosen by the user (``asset_root=``, ``MORPHKIT_ASSET_ROOT``).

    Returns
    -------
    pathlib.Path
        The root, resolved (links followed).

    Raises
    ------
    MeshError
        ``root`` is not a folder, or the mesh file does not lie inside it.
    """
    folder = Path(mesh_path).resolve().parent
    if root is None:
        return folder
    r = Path(root).resolve()
    if not r.is_dir():
        raise MeshError(expected_got("asset root", "a folder", repr(str(root))))
    if not folder.is_relative_to(r):
        raise MeshError(expected_got("asset root", f"a folder holding the mesh file {str(mesh_path)!r}",
                                     repr(str(root))))
    return r


def locate(folder: Path, name: str, root: Path, what: str) -> tuple[Path | None, bool]:
    """Find the file ``name`` that a mesh file in ``folder`` refers to, inside ``root``.

    The name is tried as written, URL-decoded, without a leading ``/`` and as its last
    component alone (as trimesh does), each relative to ``folder``; the first that lies
    inside ``root`` (links followed) and exists is taken.

    Parameters
    ----------
    folder : pathlib.Path
        The folder of the file that holds the reference (the mesh file, or its ``.mtl``).
    name : str
        The reference as written.
    root : pathlib.Path
        The asset root (:func:`asset_root`), resolved.
    what : str
        How an error names the reference (``"texture 'a.png' of mesh file 'x.obj'"``).

    Returns
    -------
    tuple
        ``(path, outside)``: the regular file found, or None; ``outside`` is True when
        the name lies outside ``root`` and no candidate inside it exists (not opened).

    Raises
    ------
    MeshError
        The file found is not a regular file (a FIFO, a device, a socket, a directory).
    """
    name = name.strip()
    candidates = dict.fromkeys((name, unquote(name), name.lstrip("/"), unquote(name).lstrip("/"),
                                os.path.basename(name), os.path.basename(unquote(name))))
    outside = False
    for cand in candidates:
        if not cand:
            continue
        path = (folder / cand).resolve()
        if not path.is_relative_to(root):
            outside = True
            continue
        try:
            mode = path.stat().st_mode
        except OSError:
            continue
        if not stat.S_ISREG(mode):
            raise MeshError(expected_got(what, "a regular file", f"{str(path)!r}: {file_kind(mode)}"))
        return path, False
    return None, outside


def _read(path: Path, what: str) -> bytes:
    """:func:`read_regular`, with the ``OSError`` of an open or a read that failed as it is."""
    fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK)
    try:
        mode = os.fstat(fd).st_mode
        if not stat.S_ISREG(mode):
            raise MeshError(expected_got(what, "a regular file", f"{str(path)!r}: {file_kind(mode)}"))
        os.set_blocking(fd, True)
        with os.fdopen(fd, "rb", closefd=False) as f:
            return f.read()
    finally:
        os.close(fd)


def read_regular(path: Path, what: str) -> bytes:
    """The bytes of ``path``, opened without blocking and read only if it is a regular file.

    Parameters
    ----------
    path : pathlib.Path
        The file.
    what : str
        What the file is, for the error message.

    Returns
    -------
    bytes
        Its content.

    Raises
    ------
    MeshError
        ``path`` is not a regular file (checked on the open file: a file swapped for a FIFO
        after :func:`locate` is refused too) or cannot be opened or read.
    """
    try:
        return _read(path, what)
    except OSError as exc:
        raise MeshError(expected_got(what, "a readable file",
                                     f"{str(path)!r} ({exc.strerror or exc})")) from exc


class AssetResolver(FilePathResolver):
    """trimesh's file resolver, confined to an asset root and to regular files (module notes).

    Parameters
    ----------
    source : str or os.PathLike
        The mesh file.
    root : pathlib.Path, optional
        The asset root (:func:`asset_root`); default the mesh file's folder.
    """

    def __init__(self, source: str | os.PathLike[str], root: Path | None = None) -> None:
        super().__init__(os.fspath(source))
        self.root = Path(root) if root is not None else Path(self.parent).resolve()
        self.source = str(source)
        #: Names refused because they lie outside the root (not opened).
        self.outside: list[str] = []
        #: Errors of references that are not regular files (trimesh swallows some of them).
        self.errors: list[MeshError] = []
        #: Image files read and checked before the load (:meth:`check_image`): their bytes,
        #: served as read then, or None for one withheld (the load goes on without it).
        self.checked: dict[Path, bytes | None] = {}

    def namespaced(self, namespace: str) -> AssetResolver:
        """A resolver for a subfolder, with the same root and the same records.

        Parameters
        ----------
        namespace : str
            The subfolder, relative to this resolver's folder.

        Returns
        -------
        AssetResolver
            Sharing :attr:`outside` and :attr:`errors` with this one.
        """
        sub = AssetResolver(os.path.join(self.parent, namespace), self.root)
        sub.outside, sub.errors, sub.checked = self.outside, self.errors, self.checked
        return sub

    def check_image(self, path: Path, what: str) -> str | None:
        """Read the image file ``path`` (found by :func:`locate`) and decode it
        (:func:`morphkit.meshes.texture.image_problem`); why it cannot be drawn, or None.

        An image that cannot be read or decoded is withheld from the load (:meth:`get` answers
        as for a missing file: the mesh loads without it); one that decodes is served from the
        bytes read here (read once: the file checked is the file drawn).

        Parameters
        ----------
        path : pathlib.Path
            The image file, resolved.
        what : str
            How an error names it.

        Returns
        -------
        str or None
            The reason, a phrase (``"cannot be read (Permission denied)"``, ``"is damaged
            (...)"``), or None.

        Raises
        ------
        MeshError
            ``path`` is not a regular file (a FIFO put in its place after :func:`locate`).
        """
        try:
            data = _read(path, what)
        except OSError as exc:
            self.checked[path] = None
            return f"cannot be read ({exc.strerror or exc})"
        why = image_problem(data)
        self.checked[path] = None if why else data
        return why

    def get(self, name: str) -> bytes:
        """The bytes of the file ``name`` refers to (:func:`locate`); refused names raise ``OSError``.

        Parameters
        ----------
        name : str
            The name as the mesh file gives it (relative to the mesh's folder, or absolute).

        Returns
        -------
        bytes
            The file's content.

        Raises
        ------
        FileNotFoundError
            No such file inside the root (one outside it is recorded in :attr:`outside`), or
            an image :meth:`check_image` withheld.
        OSError
            Not a regular file, or unreadable (recorded in :attr:`errors`).
        """
        what = f"file {name!r} referred to by mesh file {self.source!r}"
        try:
            path, outside = locate(Path(self.parent), name, self.root, what)
        except MeshError as exc:
            self.errors.append(exc)
            raise OSError(str(exc)) from exc
        if path is None:
            if outside:
                self.outside.append(name)
            raise FileNotFoundError(name)
        if path in self.checked:
            data = self.checked[path]
            if data is None:
                raise FileNotFoundError(f"{name} (withheld: it cannot be drawn)")
            return data
        try:
            return read_regular(path, what)
        except MeshError as exc:
            self.errors.append(exc)
            raise OSError(str(exc)) from exc

    def write(self, name: str, data: str | bytes) -> None:
        """Refused: loading never writes.

        Parameters
        ----------
        name : str
            The file asked for.
        data : str or bytes
            Its content (not written).
        """
        raise OSError(f"AssetResolver is read-only (asked to write {name!r})")
