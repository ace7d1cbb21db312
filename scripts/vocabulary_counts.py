"""Count the places in morphkit that bypass its shared vocabulary (issue #23).

Run from the repository root::

    python scripts/vocabulary_counts.py            # one count per line
    python scripts/vocabulary_counts.py --verbose  # and the file:line of each

What is counted (in ``morphkit/**.py``; the vocabulary's own modules excepted):

inline integer checks
    An ``if`` (or ``assert``) that refuses a value by ``isinstance(x, int)`` /
    ``np.integer`` (a type spec without ``float``: a numeric check is not an
    integer check) or by ``int(x) != x``, instead of :func:`morphkit.validate.as_int`.
    A private ``_as_int`` helper counts once as its definition. validate.py is excepted.
flag checks
    An ``if`` that refuses a value by ``not isinstance(x, bool | np.bool_)``, or a
    function named ``check_flag``/``_as_flag``, instead of :func:`morphkit.validate.as_flag`.
    validate.py is excepted.
private array validators
    A function named ``_as_array``/``_as_int``/``check_flag`` outside validate.py
    (a second copy of a validator).
bare epsilons
    A number literal ``1e-N`` in code (not in a comment or a string/docstring):
    the tokens ``grep -rnE "[^a-zA-Z_.]1e-[0-9]+" morphkit --include=*.py | grep -v tol.py``
    finds, less those in comments and docstrings and those that are the whole value of
    a module-level constant (``NAME = 1e-3``, named with its reason). tol.py is excepted.
hand-made memo dicts
    A persistent mapping (an attribute ``self.x`` / ``obj.x``, or a module-level
    name) that one function both looks up (``d.get(k)``, ``k in d``, ``k not in d``;
    a local bound to such an attribute) and fills (``d[k] = ...``), instead of
    :class:`morphkit.memo.Memo`. Counted once per (file, mapping). A local dict filled
    during one call is not a memo. memo.py is excepted.
functools caches
    Each use of ``functools.lru_cache`` / ``functools.cache`` (not hand-made, but a
    second cache vocabulary beside :class:`morphkit.memo.Memo`), reported apart.
"""

from __future__ import annotations

import argparse
import ast
import io
import re
import sys
import tokenize
from collections.abc import Iterator
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PKG = ROOT / "morphkit"
EPS = re.compile(r"^1e-[0-9]+", re.IGNORECASE)
Hit = tuple[str, int, str]
PRIVATE_VALIDATORS = ("_as_array", "_as_int", "check_flag", "_as_flag")


def _files() -> Iterator[Path]:
    yield from sorted(PKG.rglob("*.py"))


def _rel(p: Path) -> str:
    return str(p.relative_to(ROOT))


def _names(node: ast.AST) -> set[str]:
    """Names in an isinstance type spec: ``int``, ``np.integer``, ``(int, float)``, ``int | float``.

    An attribute gives its last name only (``np.integer`` -> ``integer``).
    """
    if isinstance(node, ast.Name):
        return {node.id}
    if isinstance(node, ast.Attribute):
        return {node.attr}
    out: set[str] = set()
    for child in ast.iter_child_nodes(node):
        out |= _names(child)
    return out


def _isinstance_specs(node: ast.AST) -> Iterator[set[str]]:
    for n in ast.walk(node):
        if isinstance(n, ast.Call) and isinstance(n.func, ast.Name) and n.func.id == "isinstance" \
                and len(n.args) == 2:
            yield _names(n.args[1])


def _int_ne_self(node: ast.AST) -> bool:
    """``int(x) != x`` (or ``==``) somewhere in ``node``."""
    for n in ast.walk(node):
        if isinstance(n, ast.Compare) and len(n.ops) == 1 and isinstance(n.ops[0], ast.NotEq | ast.Eq):
            sides = [n.left, n.comparators[0]]
            for a, b in (sides, sides[::-1]):
                if isinstance(a, ast.Call) and isinstance(a.func, ast.Name) and a.func.id == "int" \
                        and len(a.args) == 1 and ast.dump(a.args[0]) == ast.dump(b):
                    return True
    return False


def _raises(body: list[ast.stmt]) -> bool:
    return any(isinstance(n, ast.Raise) for s in body for n in ast.walk(s))


def _is_int_spec(s: set[str]) -> bool:
    return bool(s & {"int", "integer", "Integral"}) and not (s & {"float", "floating", "Real", "Number"})


def int_checks(path: Path, tree: ast.AST) -> list[Hit]:
    if path.name == "validate.py" and path.parent == PKG:
        return []
    hits: list[Hit] = []
    for n in ast.walk(tree):
        if isinstance(n, ast.FunctionDef) and n.name == "_as_int":
            hits.append((_rel(path), n.lineno, "def _as_int"))
            continue
        if isinstance(n, ast.If) and _raises(n.body):
            test = n.test
        elif isinstance(n, ast.Assert):
            test = n.test
        else:
            continue
        if any(_is_int_spec(s) for s in _isinstance_specs(test)) or _int_ne_self(test):
            hits.append((_rel(path), n.lineno, ast.unparse(test)[:90]))
    # an _as_int body's own checks are the one counted definition
    defs = [h for h in hits if h[2] == "def _as_int"]
    if defs:
        spans = [(f.lineno, f.end_lineno or f.lineno) for f in ast.walk(tree)
                 if isinstance(f, ast.FunctionDef) and f.name == "_as_int"]
        hits = [h for h in hits if h in defs or not any(a < h[1] <= b for a, b in spans)]
    return hits


def flag_checks(path: Path, tree: ast.AST) -> list[Hit]:
    if path.name == "validate.py" and path.parent == PKG:
        return []
    hits: list[Hit] = []
    spans = []
    for n in ast.walk(tree):
        if isinstance(n, ast.FunctionDef) and n.name in ("check_flag", "_as_flag", "_check_flag"):
            hits.append((_rel(path), n.lineno, f"def {n.name}"))
            spans.append((n.lineno, n.end_lineno or n.lineno))
    for n in ast.walk(tree):
        if not (isinstance(n, ast.If) and _raises(n.body)):
            continue
        t = n.test
        parts = t.values if isinstance(t, ast.BoolOp) and isinstance(t.op, ast.Or) else [t]
        if any(isinstance(u, ast.UnaryOp) and isinstance(u.op, ast.Not)
               and isinstance(u.operand, ast.Call) and isinstance(u.operand.func, ast.Name)
               and u.operand.func.id == "isinstance" and len(u.operand.args) == 2
               and _names(u.operand.args[1]) <= {"bool", "bool_"}
               for u in parts) and not any(a < n.lineno <= b for a, b in spans):
            hits.append((_rel(path), n.lineno, ast.unparse(n.test)[:90]))
    return hits


def private_validators(path: Path, tree: ast.AST) -> list[Hit]:
    if path.name == "validate.py" and path.parent == PKG:
        return []
    return [(_rel(path), n.lineno, f"def {n.name}") for n in ast.walk(tree)
            if isinstance(n, ast.FunctionDef) and n.name in PRIVATE_VALIDATORS]


def _named_lines(tree: ast.Module) -> set[int]:
    """Lines of module-level ``NAME = <number>`` (or ``NAME: float = <number>``): named, not bare."""
    out: set[int] = set()
    for st in tree.body:
        value = st.value if isinstance(st, ast.Assign | ast.AnnAssign) else None
        if isinstance(value, ast.Constant | ast.UnaryOp):
            out.add(st.lineno)
    return out


def epsilons(path: Path, source: str, tree: ast.Module) -> list[Hit]:
    if path.name == "tol.py" and path.parent == PKG:
        return []
    named = _named_lines(tree)
    hits: list[Hit] = []
    for tok in tokenize.generate_tokens(io.StringIO(source).readline):
        if tok.type == tokenize.NUMBER and EPS.match(tok.string) and tok.start[0] not in named:
            hits.append((_rel(path), tok.start[0], tok.line.strip()[:90]))
    return hits


def _container(node: ast.AST, aliases: dict[str, str]) -> str | None:
    """``self.x`` / ``obj.x`` -> ``.x``; a local bound to an attribute -> that attribute;
    another bare name -> the name (kept only if module-level)."""
    if isinstance(node, ast.Attribute):
        return "." + node.attr
    if isinstance(node, ast.Name):
        return aliases.get(node.id, node.id)
    return None


def _aliases(fn: ast.AST) -> dict[str, str]:
    """Locals bound to a persistent attribute: ``c = obj.x``, ``c = getattr(obj, "x", ...)``,
    ``c = obj.x = {}``."""
    out: dict[str, str] = {}
    for n in ast.walk(fn):
        if not isinstance(n, ast.Assign):
            continue
        attrs = [t.attr for t in n.targets if isinstance(t, ast.Attribute)]
        v = n.value
        if isinstance(v, ast.Attribute):
            attrs.append(v.attr)
        elif isinstance(v, ast.Call) and isinstance(v.func, ast.Name) and v.func.id == "getattr" \
                and len(v.args) >= 2 and isinstance(v.args[1], ast.Constant):
            attrs.append(str(v.args[1].value))
        if attrs:
            for t in n.targets:
                if isinstance(t, ast.Name):
                    out[t.id] = "." + attrs[0]
    return out


def memo_dicts(path: Path, tree: ast.Module) -> list[Hit]:
    if path.name == "memo.py" and path.parent == PKG:
        return []
    module_names = {t.id for s in tree.body if isinstance(s, ast.Assign | ast.AnnAssign)
                    for t in (s.targets if isinstance(s, ast.Assign) else [s.target])
                    if isinstance(t, ast.Name)}
    found: dict[str, int] = {}
    for fn in ast.walk(tree):
        if not isinstance(fn, ast.FunctionDef | ast.AsyncFunctionDef):
            continue
        aliases = _aliases(fn)
        looked: dict[str, int] = {}
        filled: set[str] = set()
        for n in ast.walk(fn):
            if isinstance(n, ast.Call) and isinstance(n.func, ast.Attribute) and n.func.attr == "get":
                c = _container(n.func.value, aliases)
                if c:
                    looked.setdefault(c, n.lineno)
            elif isinstance(n, ast.Compare) and len(n.ops) == 1 and isinstance(n.ops[0], ast.In | ast.NotIn):
                c = _container(n.comparators[0], aliases)
                if c:
                    looked.setdefault(c, n.lineno)
            elif isinstance(n, ast.Assign):
                for t in n.targets:
                    for tt in ast.walk(t):
                        if isinstance(tt, ast.Subscript):
                            c = _container(tt.value, aliases)
                            if c:
                                filled.add(c)
        for c, line in looked.items():
            if c in filled and (c.startswith(".") or c in module_names):
                found.setdefault(c, line)
    return [(_rel(path), line, name) for name, line in found.items()]


def functools_caches(path: Path, tree: ast.Module) -> list[Hit]:
    hits: list[Hit] = []
    for n in ast.walk(tree):
        if (isinstance(n, ast.Name) and n.id == "lru_cache") or (
                isinstance(n, ast.Attribute) and n.attr in ("lru_cache", "cache")
                and isinstance(n.value, ast.Name) and n.value.id == "functools"):
            hits.append((_rel(path), n.lineno, ast.unparse(n)))
    return hits


def count() -> dict[str, list[Hit]]:
    out: dict[str, list[Hit]] = {"inline integer checks": [], "flag checks": [],
                                 "private validators": [], "bare epsilons": [],
                                 "hand-made memo dicts": [], "functools caches": []}
    for p in _files():
        src = p.read_text(encoding="utf-8")
        tree = ast.parse(src)
        out["inline integer checks"] += int_checks(p, tree)
        out["flag checks"] += flag_checks(p, tree)
        out["private validators"] += private_validators(p, tree)
        out["bare epsilons"] += epsilons(p, src, tree)
        out["hand-made memo dicts"] += memo_dicts(p, tree)
        out["functools caches"] += functools_caches(p, tree)
    return out


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--verbose", "-v", action="store_true", help="list file:line of each")
    args = ap.parse_args(argv)
    for what, hits in count().items():
        files = len({h[0] for h in hits})
        print(f"{what}: {len(hits)} in {files} files")
        if args.verbose:
            for f, line, text in sorted(hits):
                print(f"    {f}:{line}: {text}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
