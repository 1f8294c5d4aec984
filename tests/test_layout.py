"""The package's layout: import arrows run one way, and no module imports itself round.

Each subpackage's docstring says what it may import; this test holds the code to
it, counting lazy imports inside functions too, so that a helper cannot creep
into the wrong room unnoticed.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

import dentopo

PACKAGE = Path(dentopo.__file__).parent

#: Subpackage -> the dentopo subpackages it may import (the top-level private modules in
#: ``PRIVATE`` are allowed everywhere).  Keep in step with the docstrings.
ALLOWED = {
    "mesh": set(),
    "sign": {"mesh"},
    "ariadne": {"mesh", "sign"},
    "topography": {"mesh"},
    "prepare": {"mesh", "topography"},
    "figures": {"mesh", "sign", "ariadne", "topography", "prepare"},
    "formats": {"mesh", "ariadne", "topography", "prepare", "figures"},
    "batch": {"mesh", "sign", "ariadne", "topography", "prepare", "formats", "samples"},
    "study": {"mesh", "sign", "ariadne", "topography", "prepare", "formats", "figures", "batch"},
    "report": {"mesh", "sign", "ariadne", "topography", "prepare", "figures", "formats", "batch"},
    "app": {
        "mesh",
        "sign",
        "ariadne",
        "topography",
        "prepare",
        "figures",
        "formats",
        "batch",
        "report",
    },
    "cli": {
        "mesh",
        "sign",
        "ariadne",
        "topography",
        "prepare",
        "figures",
        "formats",
        "batch",
        "study",
        "report",
        "app",
        "samples",
    },
    "samples": set(),
}
SUBPACKAGES = set(ALLOWED)

#: dentopo.topography's families -> the families they may import.  The shared checks at
#: topography's own level (``_parameters``, ``_units``, ``_metrics``) are open to every family
#: and import none; a family imports another only where a metric is built on it (relief
#: divides by a footprint, doolkit's OPC and relief read doolkit's slope mesh).
TOPOGRAPHY_FAMILIES = {
    "surface": set(),
    "footprint": {"surface"},
    "slope": {"surface"},
    "curvature": {"surface"},
    "dne": {"surface"},
    "occlusion": {"surface"},
    "opc": {"surface", "slope"},
    "relief": {"surface", "footprint", "slope"},
}

#: No module of the package is longer than this (lines): past it, a module holds more than
#: one concern.
MAX_LINES = 800

#: Top-level private modules every module may import; they import nothing of dentopo.
PRIVATE = {
    "dentopo._version",
    "dentopo._optional",
    "dentopo._jit",
    "dentopo._html_repr",
    "dentopo._signals",
    "dentopo._lazy_exports",
}

#: Public modules at the top level (``dentopo.NAME``) -> the subpackages they may import.  Each
#: sits beside the public API, above nothing: no subpackage may import it.
TOP_LEVEL = {
    "compat": {"mesh", "ariadne"},  # the signDNE 0.1.4 drop-in, over ariaDNE only
}


def _modules() -> dict[str, Path]:
    modules = {}
    for path in PACKAGE.rglob("*.py"):
        parts = list(path.relative_to(PACKAGE).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts = parts[:-1]
        modules[".".join(["dentopo", *parts])] = path
    return modules


def _imports(name: str, path: Path, *, lazy: bool) -> set[str]:
    """Absolute names of the dentopo modules that module `name` imports."""
    tree = ast.parse(path.read_text())
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    nodes = ast.walk(tree) if lazy else iter(tree.body)
    found = set()
    for node in nodes:
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")
                base = base[: len(base) - (node.level - 1)]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            if target.startswith("dentopo"):
                found.add(target)
                found.update(f"{target}.{alias.name}" for alias in node.names)
        elif isinstance(node, ast.Import):
            found.update(a.name for a in node.names if a.name.startswith("dentopo"))
    return found


def _subpackage(module: str) -> str | None:
    parts = module.split(".")
    return parts[1] if len(parts) > 1 and parts[1] in SUBPACKAGES else None


def test_every_subpackage_is_known_and_documented():
    on_disk = {p.name for p in PACKAGE.iterdir() if (p / "__init__.py").exists()}
    assert on_disk == SUBPACKAGES
    for name in SUBPACKAGES:
        doc = ast.get_docstring(ast.parse((PACKAGE / name / "__init__.py").read_text()))
        assert doc, f"dentopo.{name} has no docstring"
        if name not in ("samples", "cli"):
            assert "May import" in doc, f"dentopo.{name}'s docstring does not say what it imports"


@pytest.mark.parametrize("module", sorted(_modules()))
def test_imports_run_one_way(module):
    path = _modules()[module]
    own = _subpackage(module)
    if own is None:
        return  # the top level: the public API (dentopo/__init__) and shared private helpers
    wrong = set()
    for target in _imports(module, path, lazy=True):
        other = _subpackage(target)
        if other is not None and other != own and other not in ALLOWED[own]:
            wrong.add(target)
        if target in ("dentopo", "dentopo.__init__"):
            wrong.add(target)  # the public API sits above every subpackage
    assert not wrong, f"{module} imports {sorted(wrong)} against the layering"


def _top_level_modules() -> set[str]:
    """Public top-level modules (not ``__init__``/``__main__``, not private helpers)."""
    return {p.stem for p in PACKAGE.glob("*.py") if not p.stem.startswith("_")}


def test_every_top_level_module_has_a_rule():
    assert _top_level_modules() == set(TOP_LEVEL)


@pytest.mark.parametrize("name", sorted(TOP_LEVEL))
def test_top_level_modules_import_only_what_their_rule_allows(name):
    module = f"dentopo.{name}"
    path = PACKAGE / f"{name}.py"
    doc = ast.get_docstring(ast.parse(path.read_text()))
    assert doc and "May import" in doc, f"{module}'s docstring does not say what it imports"
    wrong = set()
    for target in _imports(module, path, lazy=True):
        other = _subpackage(target)
        if other is not None and other not in TOP_LEVEL[name]:
            wrong.add(target)
        if other is None and target not in PRIVATE:
            wrong.add(target)  # the public API, or another top-level module
    assert not wrong, f"{module} imports {sorted(wrong)} against its rule"


@pytest.mark.parametrize("module", sorted(_modules()))
def test_nothing_below_imports_a_top_level_module(module):
    if _subpackage(module) is None:
        return
    targets = _imports(module, _modules()[module], lazy=True)
    wrong = {t for t in targets if len(t.split(".")) > 1 and t.split(".")[1] in TOP_LEVEL}
    assert not wrong, f"{module} imports {sorted(wrong)}: top-level modules sit above it"


@pytest.mark.parametrize("module", sorted(PRIVATE))
def test_private_top_level_modules_import_nothing_of_dentopo(module):
    path = PACKAGE / f"{module.split('.')[1]}.py"
    doc = ast.get_docstring(ast.parse(path.read_text())) or ""
    assert "May import: nothing of dentopo" in doc
    assert not _imports(module, path, lazy=True)


def test_no_import_cycles():
    modules = _modules()
    graph = {
        name: {t for t in _imports(name, path, lazy=True) if t in modules and t != name}
        for name, path in modules.items()
    }
    # a package's __init__ re-exporting its own modules is not a cycle of concern
    for name in graph:
        graph[name] = {t for t in graph[name] if not name.startswith(t + ".")}
    state: dict[str, int] = {}
    stack: list[str] = []

    def visit(node):
        state[node] = 1
        stack.append(node)
        for nxt in sorted(graph[node]):
            if state.get(nxt) == 1:
                cycle = [*stack[stack.index(nxt) :], nxt]
                pytest.fail("import cycle: " + " -> ".join(cycle))
            if nxt not in state:
                visit(nxt)
        stack.pop()
        state[node] = 2

    for node in sorted(graph):
        if node not in state:
            visit(node)


def _family(module: str) -> str | None:
    parts = module.split(".")
    if len(parts) > 2 and parts[1] == "topography" and parts[2] in TOPOGRAPHY_FAMILIES:
        return parts[2]
    return None


def test_every_topography_family_is_known_and_documented():
    root = PACKAGE / "topography"
    on_disk = {p.name for p in root.iterdir() if (p / "__init__.py").exists()}
    assert on_disk == set(TOPOGRAPHY_FAMILIES)
    for name in on_disk:
        doc = ast.get_docstring(ast.parse((root / name / "__init__.py").read_text()))
        assert doc and "May import" in doc, (
            f"dentopo.topography.{name} does not say what it imports"
        )


@pytest.mark.parametrize(
    "module", sorted(m for m in _modules() if m.startswith("dentopo.topography"))
)
def test_topography_families_import_only_what_they_are_built_on(module):
    own = _family(module)
    wrong = set()
    for target in _imports(module, _modules()[module], lazy=True):
        other = _family(target)
        if other is None or other == own:
            continue
        if own is None and module != "dentopo.topography":
            wrong.add(target)  # the shared checks sit below every family
        elif own is not None and other not in TOPOGRAPHY_FAMILIES[own]:
            wrong.add(target)
    assert not wrong, f"{module} imports {sorted(wrong)} against the families' layering"


def test_no_module_is_longer_than_one_concern():
    long = {
        str(path.relative_to(PACKAGE)): n
        for path in PACKAGE.rglob("*.py")
        if (n := len(path.read_text().splitlines())) > MAX_LINES
    }
    assert not long, f"modules over {MAX_LINES} lines: {long}"
