"""The house's rules, checked on the source: layers only look down and the import graph has no
cycle.

Layers (ARCHITECTURE.md): ``geometries`` (machine descriptions) < ``twin`` (the simulator core,
its CLI included) < ``learners`` < ``validate``. A module may import its own package and the
layers below it, never a layer above; the commands of the upper layers reach ``twin``'s CLI
through the ``thermal_twin.commands`` entry points. Every import counts, also those inside
functions.
"""

from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
LAYERS = {"geometries": 0, "scenarios": 0, "twin": 1, "learners": 2, "validate": 3}


def modules() -> dict[str, Path]:
    out = {}
    for pkg in LAYERS:
        for f in (ROOT / pkg).rglob("*.py"):
            parts = f.relative_to(ROOT).with_suffix("").parts
            name = ".".join(parts[:-1] if parts[-1] == "__init__" else parts)
            out[name] = f
    return out


def imports(name: str, path: Path, known: set[str]) -> set[str]:
    """The project modules ``name`` imports (a ``from a import b`` counts as ``a.b`` when that is
    a module, else ``a``)."""
    found = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            targets = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            targets = [f"{node.module}.{a.name}" if f"{node.module}.{a.name}" in known else node.module
                       for a in node.names]
        else:
            continue
        found |= {t for t in targets if t.split(".")[0] in LAYERS and t in known and t != name}
    return found


def graph() -> dict[str, set[str]]:
    mods = modules()
    known = set(mods)
    return {name: imports(name, path, known) for name, path in mods.items()}


def test_no_module_imports_a_layer_above_its_own():
    upward = [f"{a} -> {b}" for a, deps in graph().items() for b in deps
              if LAYERS[b.split(".")[0]] > LAYERS[a.split(".")[0]]]
    assert not upward, "upward imports:\n" + "\n".join(sorted(upward))


def test_import_graph_has_no_cycle():
    """Depth-first search; a back edge is a cycle (package __init__ re-exports excluded: a package
    importing its own submodules is how it exposes its names)."""
    g = graph()
    edges = {a: {b for b in deps if not b.startswith(a + ".")} for a, deps in g.items()}
    state, cycles = {}, []

    def visit(node, path):
        state[node] = "open"
        for nxt in sorted(edges.get(node, ())):
            if state.get(nxt) == "open":
                cycles.append(" -> ".join(path[path.index(nxt):] + [nxt]) if nxt in path else f"{node} -> {nxt}")
            elif nxt not in state:
                visit(nxt, path + [nxt])
        state[node] = "done"

    for n in sorted(edges):
        if n not in state:
            visit(n, [n])
    assert not cycles, "import cycles:\n" + "\n".join(cycles)


def is_command_module(name: str) -> bool:
    """Modules that are command lines (they may print): ``twin.cli``, the ``*_cli`` modules and
    ``learners.cli``, the benchmarks (``validate.*benchmark``) and the studies run with ``python -m``."""
    last = name.rsplit(".", 1)[-1]
    return (name.startswith(("twin.cli", "validate.studies.")) or last == "cli" or last.endswith("_cli")
            or (name.startswith("validate.") and last.endswith("benchmark")))


def test_only_command_modules_print():
    """No printing from the library: a ``print`` call appears only in a command-line module; the
    library returns its text or reports progress through a callback."""
    printing = sorted(name for name, path in modules().items() if not is_command_module(name)
                      and any(isinstance(n, ast.Call) and getattr(n.func, "id", None) == "print"
                              for n in ast.walk(ast.parse(path.read_text(encoding="utf-8")))))
    assert printing == []


def test_a_script_guard_is_the_last_statement_of_its_module():
    """``if __name__ == "__main__": raise SystemExit(main())`` runs ``main`` when the module is run
    as a command (``python -m validate.studies...``); anything defined below it does not exist yet
    then, while an import (as the tests do) defines it. ``machine_b_anfis`` kept a helper below its
    guard and failed with a NameError as a command only."""
    late = []
    for name, path in modules().items():
        body = ast.parse(path.read_text(encoding="utf-8")).body
        for i, node in enumerate(body):
            if isinstance(node, ast.If) and "__name__" in ast.unparse(node.test) and i != len(body) - 1:
                late.append(f"{name}: line {node.lineno}")
    assert not late, "statements after the script guard:\n" + "\n".join(late)
