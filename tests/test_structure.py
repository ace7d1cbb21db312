"""The package's shape, checked: what the structure rules promise is true of the source.

* a module uses another module's public names only (no ``from .x import _y``);
* pyrender/OpenGL are imported by :mod:`morphkit.render` alone (the numpy/OpenCV
  core runs without a GL context);
* environment variables are read by :mod:`morphkit.settings` alone;
* nothing outside :mod:`morphkit.bench` (and the CLI's ``bench`` command)
  imports the benchmarks: scenes shared with them live in :mod:`morphkit.programs.fixtures`;
* nothing in the library imports those scenes (:mod:`morphkit.programs.fixtures`): only the
  benchmarks, the demo and the CLI (and the tests) may;
* no import cycle between modules (function-local imports count: a cycle cannot
  hide inside a function), found with Tarjan's algorithm on the import graph;
* no two parts (sub-packages and top-level modules) import each other, but for the ties still
  listed in :data:`KNOWN_TIES`;
* no module over 800 lines (one concept per module; data lives in ``morphkit/data``).

Attribute access to other objects' private members is ruff's ``SLF001``
(enabled in ``pyproject.toml``).
"""

from __future__ import annotations

import ast
import io
import re
import tokenize
from functools import cache
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parent.parent / "morphkit"
SOURCES = sorted(PACKAGE.rglob("*.py"))


def _module(path: Path) -> str:
    rel = path.relative_to(PACKAGE.parent).with_suffix("")
    parts = list(rel.parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


@cache  # the files do not change during a run: each parsed once for all the tests
def _imports(path: Path) -> list[tuple[int, str, list[str]]]:
    """``(line, absolute module, imported names)`` of every import in ``path``."""
    mod = _module(path)
    package = mod if path.name == "__init__.py" else mod.rpartition(".")[0]
    out = []
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                anchor = package.split(".")
                anchor = anchor[: len(anchor) - (node.level - 1)]
                base = ".".join(anchor + ([base] if base else []))
            out.append((node.lineno, base, [a.name for a in node.names]))
        elif isinstance(node, ast.Import):
            out.extend((node.lineno, a.name, []) for a in node.names)
    return out


def test_the_scan_sees_the_package():
    assert len(SOURCES) > 30 and any(p.name == "render.py" for p in SOURCES)


@pytest.mark.parametrize("path", SOURCES, ids=lambda p: str(p.relative_to(PACKAGE)))
def test_no_private_names_imported_across_modules(path):
    def submodule(mod: str, name: str) -> bool:  # ``from . import _kernels``: a package's own module
        folder = PACKAGE.parent.joinpath(*mod.split("."))
        return (folder / f"{name}.py").is_file() or (folder / name / "__init__.py").is_file()

    bad = [f"line {ln}: from {mod} import {name}" for ln, mod, names in _imports(path)
           for name in names if name.startswith("_") and not name.startswith("__")
           and mod.startswith("morphkit") and mod != _module(path) and not submodule(mod, name)]
    assert not bad, f"{path.name} imports private names of other modules: {bad}"


@pytest.mark.parametrize("path", SOURCES, ids=lambda p: str(p.relative_to(PACKAGE)))
def test_gl_stays_behind_the_render_module(path):
    gl = [f"line {ln}: {mod}" for ln, mod, _ in _imports(path)
          if mod.split(".")[0] in ("pyrender", "OpenGL", "pyglet")]
    if _module(path) == "morphkit.render":
        assert gl, "render.py is where pyrender is imported"
    else:
        assert not gl, f"{path.name} imports GL modules: {gl}"


@pytest.mark.parametrize("path", SOURCES, ids=lambda p: str(p.relative_to(PACKAGE)))
def test_environment_is_read_in_settings_only(path):
    uses = [n.lineno for n in ast.walk(ast.parse(path.read_text()))
            if isinstance(n, ast.Attribute) and n.attr in ("environ", "getenv")]
    if _module(path) != "morphkit.settings":
        assert not uses, f"{path.name} reads the environment at lines {uses}: use morphkit.settings"


@pytest.mark.parametrize("path", SOURCES, ids=lambda p: str(p.relative_to(PACKAGE)))
def test_only_the_bench_and_the_cli_import_the_bench(path):
    mod = _module(path)
    if mod.startswith("morphkit.bench") or mod == "morphkit.cli":
        return
    bad = [f"line {ln}: {m}" for ln, m, _ in _imports(path) if m.startswith("morphkit.bench")]
    assert not bad, f"{path.name} imports the benchmark: {bad}"


#: The modules that may use the demo/bench/test scenes of :mod:`morphkit.programs.fixtures`; the
#: rest is the library, which must not depend on its own test scenes.
FIXTURE_USERS = ("morphkit.programs.fixtures", "morphkit.imaging.fidelity", "morphkit.bench",
                 "morphkit.programs.demo", "morphkit.cli")

#: The fixture modules: the demo/bench/test scenes and the renderer's fidelity scenes.
FIXTURES = ("morphkit.programs.fixtures", "morphkit.imaging.fidelity")


def _imports_fixtures(path: Path) -> list[str]:
    return [f"line {ln}: {m}" for ln, m, names in _imports(path)
            if any(m == f or m.startswith(f"{f}.") or any(f"{m}.{n}" == f for n in names)
                   for f in FIXTURES)]


@pytest.mark.parametrize("path", SOURCES, ids=lambda p: str(p.relative_to(PACKAGE)))
def test_the_library_does_not_import_the_fixtures(path):
    mod = _module(path)
    if any(mod == u or mod.startswith(u + ".") for u in FIXTURE_USERS):
        return
    bad = _imports_fixtures(path)
    assert not bad, f"{path.name} imports the test scenes (morphkit.programs.fixtures): {bad}"


def test_the_fixture_scan_sees_the_demo_import_them():
    """The check above can fail: the demo's imports of the fixtures are found."""
    assert _imports_fixtures(PACKAGE / "programs" / "demo.py")
    assert not (PACKAGE / "scenes.py").exists()  # one module of scenes: morphkit.programs.fixtures


@cache
def _graph() -> dict[str, set[str]]:
    """Module -> the morphkit modules it imports (at any depth of the file: a
    function-local import counts, so a cycle cannot be hidden inside a function)."""
    modules = {_module(p): p for p in SOURCES}
    graph: dict[str, set[str]] = {}
    for mod, path in modules.items():
        deps = set()
        for _, target, names in _imports(path):
            if not target.startswith("morphkit"):
                continue
            # ``from .pkg import mod`` imports the submodule ``pkg.mod`` when it is one
            subs = {f"{target}.{n}" for n in names if f"{target}.{n}" in modules}
            deps |= subs or ({target} if target in modules else set())
        graph[mod] = deps - {mod}
    return graph


def _cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components with more than one module (Tarjan)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on: set[str] = set()
    out: list[list[str]] = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in graph.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return out


def _parents(mod: str) -> set[str]:
    parts = mod.split(".")
    return {".".join(parts[:k]) for k in range(1, len(parts))}


def test_the_cycle_finder_finds_a_cycle():
    assert _cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]
    assert _cycles({"a": {"b"}, "b": set()}) == []


def test_no_import_cycle_between_modules():
    # a package's __init__ re-exports its modules, which import siblings through the
    # package: edges into a module's own parent packages are not cycles of design
    graph = {m: {d for d in deps if d not in _parents(m)} for m, deps in _graph().items()}
    assert _cycles(graph) == [], "import cycles (each a set of modules that import each other)"


@pytest.mark.parametrize("path", SOURCES, ids=lambda p: str(p.relative_to(PACKAGE)))
def test_no_module_over_800_lines(path):
    n = len(path.read_text().splitlines())
    assert n <= 800, f"{path.name} has {n} lines: split it by concept (one concept per module)"


def _part(mod: str) -> str:
    """The part a module belongs to: its sub-package, or itself for a top-level module."""
    parts = mod.split(".")
    return parts[1] if len(parts) > 1 else parts[0]


def _ties(graph: dict[str, set[str]]) -> set[tuple[str, str]]:
    """Pairs of parts that import each other (each pair sorted), from a module graph."""
    edges = {(_part(m), _part(d)) for m, deps in graph.items() for d in deps}
    edges = {(a, b) for a, b in edges if a != b and "morphkit" not in (a, b)}
    return {tuple(sorted((a, b))) for a, b in edges if (b, a) in edges}


#: The two-way ties between parts still standing, each with what holds it (none: a tie that
#: comes back fails :func:`test_no_two_parts_import_each_other`).
KNOWN_TIES: set[tuple[str, str]] = set()


def test_the_tie_finder_finds_a_tie():
    graph = {"morphkit.a.x": {"morphkit.b.y"}, "morphkit.b.y": {"morphkit.a.z"},
             "morphkit.c": {"morphkit.a.x"}}
    assert _ties(graph) == {("a", "b")}


def test_no_two_parts_import_each_other():
    """A part is a sub-package or a top-level module; lazy and TYPE_CHECKING imports count."""
    ties = _ties(_graph())
    assert ties <= KNOWN_TIES, f"new two-way ties between parts: {sorted(ties - KNOWN_TIES)}"
    assert ties == KNOWN_TIES, f"ties gone, drop them from KNOWN_TIES: {sorted(KNOWN_TIES - ties)}"


#: The floors of the package, lowest first: a part imports only parts of its own floor or below.
#: The core's foundations (top-level modules) and its sub-packages share the lowest floor; the
#: two papers' wings share the next one and do not import each other (paper 2's billboards use
#: its view morph, the same paper); the junction of both papers is above them, the bake pipeline
#: and the export to glTF (both read the junction's sun atlases) above that, then the programs,
#: the benchmarks (which use the programs' scenes), and the command line over everything.
FLOORS: tuple[frozenset[str], ...] = (
    frozenset({"conventions", "tol", "errors", "validate", "settings", "protocols", "camera", "scene",
               "render", "glplatform", "passes", "memo", "sunpath", "files", "imaging", "meshes", "warp",
               "views"}),
    frozenset({"shadow", "billboard", "viewmorph"}),
    frozenset({"sunlit", "scenes"}),
    frozenset({"bake", "export"}),
    frozenset({"plan"}),
    frozenset({"programs"}),
    frozenset({"bench"}),
    frozenset({"cli", "__main__"}),
)

#: The papers' wings, which share a floor but must not import each other.
WINGS = {"shadow": "paper 1", "billboard": "paper 2", "viewmorph": "paper 2"}


def _floor(part: str) -> int:
    return next(i for i, floor in enumerate(FLOORS) if part in floor)


def test_every_part_has_a_floor():
    parts = {_part(m) for m in _graph()} - {"morphkit"}
    assert parts == set().union(*FLOORS), (
        f"parts without a floor: {sorted(parts - set().union(*FLOORS))}; "
        f"floors naming no part: {sorted(set().union(*FLOORS) - parts)}")


def test_parts_import_only_their_floor_or_below():
    """The layers drawn by the folder names: core -> wings -> junction -> bake -> programs -> bench."""
    up = sorted({f"{m} -> {d}" for m, deps in _graph().items() for d in deps
                 if "morphkit" not in (_part(m), _part(d)) and _floor(_part(d)) > _floor(_part(m))})
    assert not up, f"imports of a higher floor: {up}"


def test_the_wings_do_not_import_each_other():
    across = sorted({f"{m} -> {d}" for m, deps in _graph().items() for d in deps
                     if _part(m) in WINGS and _part(d) in WINGS and WINGS[_part(m)] != WINGS[_part(d)]})
    assert not across, f"one paper's wing imports the other's: {across}"


def test_the_floor_check_can_fail():
    assert _floor("billboard") > _floor("imaging") and _floor("sunlit") > _floor("shadow")
    assert _floor("bench") > _floor("programs")


def _folders() -> list[Path]:
    return sorted({p.parent for p in SOURCES})


@pytest.mark.parametrize("folder", _folders(), ids=lambda p: str(p.relative_to(PACKAGE.parent)))
def test_no_folder_holds_more_than_15_modules(folder):
    """A folder that grows past 15 modules is split into sub-folders by role (method,
    extensions, baselines and truths, file formats, bake time)."""
    modules = sorted(p.name for p in folder.glob("*.py") if p.name != "__init__.py")
    assert len(modules) <= 15, f"{folder.name}/ holds {len(modules)} modules: {modules}"


#: An issue reference in code text: ``#26``, ``issue 25``, ``issues #26 and #27``.
ISSUE_REF = re.compile(r"(?<![\w&/#])#\d{1,4}(?![\w-])|\bissues? #?\d+", re.IGNORECASE)


def _issue_refs(source: str) -> list[str]:
    """Issue references in a module's comments and string literals (docstrings among them)."""
    found = []
    for tok in tokenize.generate_tokens(io.StringIO(source).readline):
        if tok.type == tokenize.COMMENT:
            text = tok.string[1:]
        elif tok.type == tokenize.STRING:
            text = tok.string
        else:
            continue
        found += [f"line {tok.start[0]}: {m.group(0)}" for m in ISSUE_REF.finditer(text)]
    return found


def test_the_issue_scan_finds_references():
    src = '"""Built for issue #26."""\nx = 1  # see #29\ny = "#ff0000"  # noqa: E501\nz = 2  # 1. then 2.\n'
    assert _issue_refs(src) == ["line 1: issue #26", "line 2: #29"]
    assert _issue_refs('z = "#123abc"  # colour\n') == []
    src = '# named (#23: values unchanged)\n"""Issue 25 and issues #26 and #27."""\n'
    assert _issue_refs(src) == ["line 1: #23", "line 2: Issue 25", "line 2: issues #26", "line 2: #27"]
    legit = 'c = "#fff"  # type: ignore[attr-defined]\nu = "a.html#12x"  # 2. step; &#39;\nk = 1  # 3x3\n'
    assert _issue_refs(legit) == []


#: The GLSL shaders morphkit ships (their ``//`` comments are code text too).
SHADERS = sorted(p for p in (PACKAGE / "data" / "shaders").glob("*") if p.suffix in {".frag", ".vert"})


def _shader_issue_refs(text: str) -> list[str]:
    """Issue references in a shader's ``//`` comments (``#version 330``, ``#ifdef`` are code)."""
    return [f"line {i}: {m.group(0)}" for i, line in enumerate(text.splitlines(), 1)
            if "//" in line for m in ISSUE_REF.finditer(line.split("//", 1)[1])]


def test_the_shader_scan_finds_references():
    src = "#version 330 core\n// the one-pass frame (issue #26)\n"
    assert _shader_issue_refs(src) == ["line 2: issue #26"]
    assert _shader_issue_refs("#define MAX_LIGHTS 8\nvec4 c; // 1. a colour, #ff8800\n") == []


@pytest.mark.parametrize("path", SHADERS, ids=lambda p: p.name)
def test_shader_comments_name_no_issue_numbers(path):
    refs = _shader_issue_refs(path.read_text())
    assert not refs, f"{path.name} names issues in its comments: {refs}"


@pytest.mark.parametrize("path", SOURCES, ids=lambda p: str(p.relative_to(PACKAGE)))
def test_code_text_names_no_issue_numbers(path):
    """Code text teaches; the history of a change is in the commits and docs/CHANGELOG."""
    refs = _issue_refs(path.read_text())
    assert not refs, f"{path.name} names issues in its code text: {refs}"
