"""The layers and walls of the code base, read from the imports of every module.

- ``algorithms`` never imports ``service`` or ``morphserve`` (it is a library of its own);
- a family of ``algorithms`` never imports another family's private module
  (``algorithms.layout._inputs`` from ``algorithms.embedding``): what families share lives in
  ``algorithms.core`` or in a family's public modules;
- ``service`` imports no private module of ``algorithms`` (``algorithms.x._y``): the service
  uses what the library publishes;
- ``morphserve`` (the SDK) imports neither ``service`` nor ``algorithms``.

Every import counts, those inside functions too.
"""

from __future__ import annotations

import ast
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("algorithms", "service", "morphserve")


def _module_name(path: Path) -> str:
    parts = list(path.relative_to(ROOT).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def _imports(path: Path) -> list[tuple[int, str]]:
    """(line, imported module) of every import in a file, relative ones resolved; ``from a
    import b`` counts as importing ``a.b`` too (b may be a module)."""
    tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
    here = _module_name(path).split(".")
    package = here if path.name == "__init__.py" else here[:-1]
    out = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            out += [(node.lineno, a.name) for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                base = ".".join(package[:len(package) - node.level + 1] + ([base] if base else []))
            out.append((node.lineno, base))
            out += [(node.lineno, f"{base}.{a.name}") for a in node.names if a.name != "*"]
    return out


def _files(package: str) -> list[Path]:
    return sorted((ROOT / package).rglob("*.py"))


def _private_part(module: str) -> str | None:
    """The first private component of a dotted module name (``_inputs`` in
    ``algorithms.layout._inputs.x``), or None."""
    return next((p for p in module.split(".")[1:] if p.startswith("_") and
                 not p.startswith("__")), None)


def _family(module: str) -> str | None:
    parts = module.split(".")
    return parts[1] if len(parts) > 1 and parts[0] == "algorithms" else None


def _violations(package: str) -> list[str]:
    bad: dict[str, str] = {}  # one entry per import statement: its first offending name
    for path in _files(package):
        me = _module_name(path)
        for line, target in _imports(path):
            key = f"{path.relative_to(ROOT)}:{line}"
            if key in bad:
                continue
            where = f"{key} imports {target}"
            top = target.split(".")[0]
            if ((package == "algorithms" and top in ("service", "morphserve"))
                    or (package == "morphserve" and top in ("service", "algorithms"))
                    or (top == "algorithms" and _private_part(target) is not None
                        and (package != "algorithms" or _family(target) != _family(me)))):
                bad[key] = where
    return list(bad.values())


@pytest.mark.parametrize("package", PACKAGES)
def test_layers_and_walls(package: str) -> None:
    assert _violations(package) == []


def test_the_walk_sees_what_it_should(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """The reader finds imports inside functions and resolves relative ones."""
    fake = tmp_path / "algorithms" / "embedding"
    fake.mkdir(parents=True)
    (tmp_path / "algorithms" / "__init__.py").write_text("")
    (fake / "__init__.py").write_text("")
    (fake / "x.py").write_text(
        "from . import _mine\n"
        "def f():\n"
        "    from algorithms.layout._inputs import g\n"
        "    import service.app\n")
    monkeypatch.setattr(sys.modules[__name__], "ROOT", tmp_path)
    assert _violations("algorithms") == [
        "algorithms/embedding/x.py:3 imports algorithms.layout._inputs",
        "algorithms/embedding/x.py:4 imports service.app",
    ]
