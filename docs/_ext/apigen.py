"""Sphinx extension: the API reference of every public morphkit name, generated at build time.

At ``builder-inited`` it walks the package (:func:`pkgutil.walk_packages`; any module or package
whose name has a part starting with ``_`` is private and skipped) and writes ``docs/api/``: an
index and one page per module. A module's public names are its ``__all__``; a module without
``__all__`` (``morphkit.tol``) contributes every top-level name it assigns, defines or declares
that does not start with ``_``. So a new subpackage appears in the reference as soon as it is
merged, with no list to update.

Each object is documented once, on the page of the module that defines it (its ``__module__``
for classes and functions, the module whose source assigns it for data). A package that
re-exports names lists them in a table linking to those pages, and references to the
re-exported or imported spelling (``morphkit.shadow.ShadowAtlas``, ``ShadowAtlas`` inside
:mod:`morphkit.shadow`, ``tol.RAY_OFFSET`` where ``tol`` is imported) are resolved to the
defining page by :func:`resolve_alias`; a reference that reaches nothing documented still
fails the build (``nitpicky``).

Checks beyond numpydoc's validation: module data needs a ``#:`` comment (:func:`data_docstring`);
what numpydoc's parser only warns about (an unknown section) fails (:func:`docstring_sections`).
"""

from __future__ import annotations

import ast
import importlib
import importlib.util
import inspect
import pkgutil
import re
import types
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, TypeVar

from docutils import nodes
from sphinx.application import Sphinx
from sphinx.errors import PycodeError
from sphinx.pycode import ModuleAnalyzer
from sphinx.util import logging

logger = logging.getLogger(__name__)

PACKAGE = "morphkit"

#: (id(object), name) -> canonical dotted name of every documented public module-level object,
#: and the names of the public modules; filled by :func:`collect`.
_HOME: dict[tuple[int, str], str] = {}
_MODULES: set[str] = set()


@dataclass
class ModuleInfo:
    """The public names of one module, split by where they are defined."""

    name: str
    has_all: bool
    classes: list[str] = field(default_factory=list)
    exceptions: list[str] = field(default_factory=list)
    functions: list[str] = field(default_factory=list)
    data: list[str] = field(default_factory=list)
    reexports: list[tuple[str, str]] = field(default_factory=list)  # (name, canonical dotted name)
    other: list[tuple[str, str]] = field(default_factory=list)  # (name, description) e.g. modules


def _public_modules() -> list[str]:
    """morphkit and every module and package below it whose dotted name has no ``_`` part."""
    pkg = importlib.import_module(PACKAGE)
    names = [info.name for info in pkgutil.walk_packages(pkg.__path__, PACKAGE + ".")]
    return sorted([PACKAGE, *[n for n in names if not any(p.startswith("_") for p in n.split("."))]])


def _assigned_names(module: types.ModuleType) -> list[str]:
    """Top-level names a module's source assigns, defines or declares (not imports), in order."""
    tree = ast.parse(Path(inspect.getfile(module)).read_text(encoding="utf-8"))
    names: list[str] = []
    for node in tree.body:
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
            names.append(node.name)
        elif isinstance(node, ast.Assign):
            names += [t.id for t in node.targets if isinstance(t, ast.Name)]
        elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
            names.append(node.target.id)
    return list(dict.fromkeys(names))


def _public_names(module: types.ModuleType) -> tuple[list[str], bool]:
    if hasattr(module, "__all__"):
        return list(module.__all__), True
    return [n for n in _assigned_names(module) if not n.startswith("_")], False


def collect() -> tuple[dict[str, ModuleInfo], dict[str, str]]:
    """Every public module's :class:`ModuleInfo`, and the map re-exported name -> canonical name."""
    mods = {name: importlib.import_module(name) for name in _public_modules()}
    _MODULES.clear()
    _MODULES.update(mods)
    public = {name: _public_names(m) for name, m in mods.items()}
    assigned = {name: set(_assigned_names(m)) for name, m in mods.items()}

    def defined_here(modname: str, n: str) -> bool:
        obj = getattr(mods[modname], n, None)
        if inspect.isclass(obj) or inspect.isroutine(obj):
            return getattr(obj, "__module__", None) == modname
        return n in assigned[modname] and not inspect.ismodule(obj)

    # Where each public object is documented: (id(object), name) -> canonical dotted name (the
    # name is part of the key: equal small ints or strings are one object in CPython).
    home = _HOME
    home.clear()
    for modname, m in mods.items():
        for n in public[modname][0]:
            if hasattr(m, n) and defined_here(modname, n):
                home.setdefault((id(getattr(m, n)), n), f"{modname}.{n}")
    infos: dict[str, ModuleInfo] = {}
    aliases: dict[str, str] = {}
    for modname, m in mods.items():
        names, has_all = public[modname]
        info = ModuleInfo(modname, has_all)
        for n in names:
            if not hasattr(m, n):
                logger.warning("apigen: %s.__all__ names %r, which the module does not define", modname, n)
                continue
            obj = getattr(m, n)
            if inspect.ismodule(obj):
                info.other.append((n, obj.__name__))
                continue
            canonical = home.get((id(obj), n))
            if canonical is not None and canonical != f"{modname}.{n}" and not defined_here(modname, n):
                info.reexports.append((n, canonical))
                aliases[f"{modname}.{n}"] = canonical
            elif inspect.isclass(obj) and issubclass(obj, BaseException):
                info.exceptions.append(n)
            elif inspect.isclass(obj):
                info.classes.append(n)
            elif inspect.isroutine(obj):
                info.functions.append(n)
            else:
                info.data.append(n)
        infos[modname] = info
    return infos, aliases


def _title(text: str, char: str) -> list[str]:
    return [text, char * len(text), ""]


def _table(names: list[str]) -> list[str]:
    return [".. autosummary::", "   :nosignatures:", "", *[f"   {n}" for n in names], ""]


def module_page(info: ModuleInfo) -> str:
    """The reST of one module's reference page."""
    lines = _title(info.name, "=")
    lines += [f".. automodule:: {info.name}", "", f".. currentmodule:: {info.name}", ""]
    local = info.classes + info.exceptions + info.functions + info.data
    if not info.has_all:
        lines += ["This module has no ``__all__``: every top-level name it defines that does not",
                  "start with ``_`` is listed.", ""]
    if local:
        lines += _title("Summary", "-") + _table(local)
    if info.reexports:
        lines += _title("Re-exported names", "-")
        lines += [f"Defined in submodules and importable from :mod:`{info.name}`.", ""]
        # names below this package relative to it (autosummary refuses the package's own prefix)
        lines += _table([f"~{c[len(info.name) + 1:]}" if c.startswith(info.name + ".") else f"~{c}"
                         for _, c in info.reexports])
    if info.other:
        lines += _title("Modules", "-")
        lines += [f"* ``{n}``: the module ``{target}``" for n, target in info.other] + [""]
    for heading, names, directive in (("Classes", info.classes, "autoclass"),
                                      ("Exceptions", info.exceptions, "autoexception"),
                                      ("Functions", info.functions, "autofunction"),
                                      ("Data", info.data, "autodata")):
        if not names:
            continue
        lines += _title(heading, "-")
        for n in names:
            lines += [f".. {directive}:: {n}"]
            if directive in ("autoclass", "autoexception"):
                lines += ["   :members:", "   :undoc-members:"]
                if getattr(importlib.import_module(info.name), n).__bases__ != (object,):
                    lines += ["   :show-inheritance:"]
            lines += [""]
    return "\n".join(lines)


def index_page(infos: dict[str, ModuleInfo]) -> str:
    """The reST of the reference's index: every module with its one-line summary."""
    lines = _title("API reference", "=")
    lines += [
        "Every public name of morphkit, one page per module, generated from the docstrings at",
        "build time. A module's public names are its ``__all__``; each object is documented",
        "on the page of the module that defines it, and packages list what they re-export.",
        "",
        ".. autosummary::",
        "",
        *[f"   {name}" for name in infos],
        "",
        ".. toctree::",
        "   :hidden:",
        "",
        *[f"   {name}" for name in infos],
        "",
    ]
    return "\n".join(lines)


def _write_if_changed(path: Path, text: str) -> None:
    if not path.exists() or path.read_text(encoding="utf-8") != text:
        path.write_text(text, encoding="utf-8")


def generate(app: Sphinx) -> None:
    """Write ``api/`` under the source directory (pages unchanged are left alone)."""
    infos, aliases = collect()
    app.env.morphkit_aliases = aliases  # type: ignore[attr-defined]
    # numpydoc validates an object's own __doc__; module data is checked by data_docstring.
    data = [f"{info.name}.{n}" for info in infos.values() for n in info.data]
    if data and app.config.numpydoc_validation_checks:
        patterns = [p.pattern for p in [app.config.numpydoc_validation_excluder] if p is not None]
        patterns.append("^(?:" + "|".join(re.escape(d) for d in data) + ")$")
        app.config.numpydoc_validation_excluder = re.compile("|".join(patterns))
    out = Path(app.srcdir) / "api"
    out.mkdir(exist_ok=True)
    wanted = {f"{name}.rst" for name in infos} | {"index.rst"}
    for stale in out.glob("*.rst"):
        if stale.name not in wanted:
            stale.unlink()
    _write_if_changed(out / "index.rst", index_page(infos))
    for name, info in infos.items():
        _write_if_changed(out / f"{name}.rst", module_page(info))


def _lookup(dotted: str) -> Any:
    """The object a dotted name under morphkit names, or None."""
    parts = dotted.split(".")
    if parts[0] != PACKAGE:
        return None
    for i in range(len(parts), 0, -1):
        try:
            obj: Any = importlib.import_module(".".join(parts[:i]))
        except ImportError:
            continue
        try:
            for attr in parts[i:]:
                obj = getattr(obj, attr)
        except AttributeError:
            return None
        return obj
    return None


def _canonical(dotted: str, aliases: dict[str, str]) -> str | None:
    """Where the object a dotted name reaches is documented, or None when it is not a morphkit object.

    Follows package re-exports (``aliases``) and imports: ``morphkit.shadow.frame.tol.RAY_OFFSET``
    (``tol`` imported into ``frame``) is ``morphkit.tol.RAY_OFFSET``, ``ShadowAtlas.save`` seen
    from any module that imports ``ShadowAtlas`` is ``morphkit.shadow.atlas.ShadowAtlas.save``.
    """
    parts = dotted.split(".")
    for i in range(len(parts), 0, -1):
        prefix = ".".join(parts[:i])
        if prefix in _MODULES:  # a submodule wins over a package attribute of the same name
            break
        if prefix in aliases:
            return ".".join([aliases[prefix], *parts[i:]])
    obj = _lookup(dotted)
    if obj is None:
        return None
    if inspect.ismodule(obj):
        return obj.__name__
    if (inspect.isclass(obj) or inspect.isroutine(obj)) and hasattr(obj, "__qualname__"):
        if str(getattr(obj, "__module__", "")).startswith(PACKAGE + "."):
            return f"{obj.__module__}.{obj.__qualname__}"
    parent, _, last = dotted.rpartition(".")
    owner = _lookup(parent)
    if inspect.ismodule(owner):
        return _HOME.get((id(obj), last))
    if inspect.isclass(owner):
        owner_name = _canonical(parent, aliases)
        return f"{owner_name}.{last}" if owner_name else None
    return None


def resolve_alias(app: Sphinx, env: Any, node: nodes.Element, contnode: nodes.Element) -> Any:
    """Resolve a Python reference through re-exports and imports to the page that documents it.

    A reference is looked up as written and relative to the module (and class) it appears in;
    the object it reaches is found where apigen documented it. A type variable (``F`` in
    ``compile_kernel(fn: F) -> F``) has no page; a reference to one is shown as text.
    """
    if node.get("refdomain") != "py":
        return None
    aliases: dict[str, str] = getattr(env, "morphkit_aliases", {})
    target = node["reftarget"].lstrip(".~")
    modname, clsname = node.get("py:module"), node.get("py:class")
    candidates = [target]
    if modname:
        candidates.insert(0, f"{modname}.{target}")
        if clsname:
            candidates.insert(0, f"{modname}.{clsname}.{target}")
    domain = env.get_domain("py")

    def resolve(name: str, specific: bool = False) -> Any:
        new_node = node.deepcopy()
        new_node["reftarget"] = name
        new_node["refspecific"] = specific
        for reftype in (node["reftype"], "obj"):
            found = domain.resolve_xref(env, node["refdoc"], app.builder, reftype, name, new_node, contnode)
            if found is not None:
                return found
        return None

    reached = False
    for cand in candidates:
        obj = _lookup(cand)
        reached = reached or obj is not None
        if isinstance(obj, TypeVar):
            return contnode
        canonical = _canonical(cand, aliases)
        if canonical is not None and (found := resolve(canonical)) is not None:
            return found
        # An instance attribute listed in its class's "Attributes" section: link to the class.
        owner, _, attr = cand.rpartition(".")
        owner_name = _canonical(owner, aliases) if inspect.isclass(_lookup(owner)) else None
        if owner_name and attr in _attributes_section(_lookup(owner)):
            return resolve(owner_name)
    if not reached and not target.startswith(PACKAGE + "."):
        # A name no candidate module defines, written short (``ShadowMethod`` in a module that
        # does not import it): the one documented object whose dotted name ends with it, if
        # exactly one does (several: Sphinx warns that the reference is ambiguous) -- or, for
        # ``Class.attr``, the class when its "Attributes" section lists ``attr``.
        found = resolve(target, specific=True)
        owner, _, attr = target.rpartition(".")
        if found is None and owner:
            matches = domain.find_obj(env, None, None, owner, "class", 1)
            if len(matches) == 1 and attr in _attributes_section(_lookup(matches[0][0])):
                return resolve(matches[0][0])
        return found
    return None


def _attributes_section(cls: Any) -> set[str]:
    """The names a class's numpydoc "Attributes" section documents."""
    from numpydoc.docscrape import NumpyDocString

    if not inspect.isclass(cls):
        return set()
    try:
        section = NumpyDocString(inspect.getdoc(cls) or "")["Attributes"]
    except Exception:  # a malformed docstring is for numpydoc to report
        return set()
    return {name.strip() for param in section for name in param.name.split(",")}


def external_reference(app: Sphinx, domain: Any, node: nodes.Element) -> bool | None:
    """Keep quiet about references to other packages' names (numpy, OpenCV, trimesh, ...).

    The build runs offline, so there is no intersphinx inventory to link them with. A target
    is external when its first dotted part is an importable top-level module other than
    morphkit (``numpy.ndarray``, ``cv2.remap``); anything else that did not resolve -- a
    morphkit name, or an unqualified name that no module around it defines -- stays a warning
    (``nitpicky``), so a broken reference fails the build.
    """
    if node.get("refdomain") != "py":
        return None
    first = node["reftarget"].lstrip("~.").split(".")[0]
    first = {"np": "numpy"}.get(first, first)
    if first == PACKAGE or "." not in node["reftarget"]:
        return None
    try:
        external = importlib.util.find_spec(first) is not None
    except (ImportError, ValueError):
        external = False
    return True if external else None


def public_bases(app: Sphinx, name: str, obj: Any, options: Any, bases: list[Any]) -> None:
    """Show a private base class (``_AtlasMethod``) as its own public bases, which have pages."""
    i = 0
    while i < len(bases):
        base = bases[i]
        if getattr(base, "__name__", "").startswith("_") and isinstance(base, type):
            bases[i:i + 1] = [b for b in base.__bases__ if b not in bases]
            continue
        i += 1


def dataclass_signature(app: Sphinx, what: str, name: str, obj: Any, options: Any, signature: str | None,
                        return_annotation: str | None) -> tuple[str | None, str | None] | None:
    """Show a dataclass field's ``default_factory`` as ``...``: ``<factory>`` is not Python, and
    Sphinx would fall back to splitting the whole signature at every comma."""
    if signature and "<factory>" in signature:
        return signature.replace("<factory>", "..."), return_annotation
    return None


def data_docstring(app: Sphinx, what: str, name: str, obj: Any, options: Any, lines: list[str]) -> None:
    """Module data: its docstring is the ``#:`` comment above its assignment, and it must have one.

    Without one autodoc would show the docstring of the value's type (``str(object='')``), and
    numpydoc's GL08 looks at that same ``__doc__``: so data is checked here instead (see
    :func:`generate`, which keeps numpydoc's validation off module data).
    """
    if what != "data" or not name.startswith(PACKAGE + "."):
        return
    modname, _, attr = name.rpartition(".")
    try:
        attr_docs = ModuleAnalyzer.for_module(modname).find_attr_docs()
    except PycodeError:
        attr_docs = {}
    if ("", attr) not in attr_docs:
        lines[:] = []
        logger.warning("apigen: %s has no docstring (add a '#:' comment above its assignment)", name)


def docstring_sections(app: Sphinx, what: str, name: str, obj: Any, options: Any, lines: list[str]
                       ) -> None:
    """Fail on what numpydoc's parser only warns about in Python (an unknown section such as
    ``Convention`` is dropped from the page); runs before numpydoc rewrites ``lines``."""
    if what == "module" or not name.startswith(PACKAGE + "."):
        return
    from numpydoc.docscrape import NumpyDocString

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        NumpyDocString("\n".join(lines))
    for w in caught:
        logger.warning("apigen: %s: %s", name, str(w.message).splitlines()[0])


def setup(app: Sphinx) -> dict[str, Any]:
    """Register the generator, the alias resolver and the checks."""
    app.connect("builder-inited", generate)
    app.connect("missing-reference", resolve_alias)
    app.connect("warn-missing-reference", external_reference)
    app.connect("autodoc-process-bases", public_bases)
    app.connect("autodoc-process-docstring", data_docstring)
    app.connect("autodoc-process-docstring", docstring_sections, priority=400)
    app.connect("autodoc-process-signature", dataclass_signature)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
