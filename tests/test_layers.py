"""The package's layers: no import cycle, no upward import (function-level imports count).

Layers, lowest first, by the first name under ``spectral_contact``:
errors, units < physics < numerics < result < solvers, reference < api < instruments < the rest
(cli, ...).  A module may import from its own layer and the layers below (README, "How it works").
"""
import ast
from pathlib import Path

import pytest

PKG = Path(__file__).resolve().parents[1] / "spectral_contact"
LAYERS = [("errors", "units", "constants"), ("physics",), ("numerics",), ("result", "results"),
          ("solvers", "reference"), ("api",), ("instruments",)]


def _layer(mod: str) -> int:
    parts = mod.split(".")
    head = parts[1] if len(parts) > 1 else ""
    return next((i for i, names in enumerate(LAYERS) if head in names), len(LAYERS))


def _modules() -> dict:
    mods = {}
    for p in PKG.rglob("*.py"):
        name = ".".join(("spectral_contact",) + p.relative_to(PKG).with_suffix("").parts)
        mods[name.removesuffix(".__init__")] = p
    return mods


def import_graph() -> dict:
    """module -> set of package modules it imports (anywhere in its body)."""
    mods = _modules()
    graph = {}
    for m, p in mods.items():
        deps = set()
        for node in ast.walk(ast.parse(p.read_text())):
            if isinstance(node, ast.Import):
                names = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom):
                base = m.split(".")
                if node.level:
                    if p.name != "__init__.py":
                        base = base[:-1]
                    base = base[: len(base) - (node.level - 1)]
                    prefix = ".".join(base + ([node.module] if node.module else []))
                else:
                    prefix = node.module or ""
                names = [prefix] + [f"{prefix}.{a.name}" for a in node.names]
            else:
                continue
            deps |= {t for t in names if t in mods and t != m and not m.startswith(t + ".")}
        graph[m] = deps
    return graph


def problems(graph: dict) -> list:
    out = [f"upward import: {m} -> {t}" for m, deps in sorted(graph.items())
           for t in sorted(deps) if _layer(t) > _layer(m)]
    # cycles: a module that reaches itself
    for start in sorted(graph):
        seen, stack = set(), list(graph[start])
        while stack:
            v = stack.pop()
            if v == start:
                out.append(f"import cycle through {start}")
                break
            if v not in seen:
                seen.add(v)
                stack.extend(graph[v])
    return out


def test_no_cycles_and_no_upward_imports():
    graph = import_graph()
    assert len(graph) > 30
    assert problems(graph) == []


@pytest.mark.parametrize("bad, expected", [
    ({"spectral_contact.physics.a": {"spectral_contact.api"}, "spectral_contact.api": set()},
     "upward import"),
    ({"spectral_contact.solvers.a": {"spectral_contact.solvers.b"},
      "spectral_contact.solvers.b": {"spectral_contact.solvers.a"}}, "import cycle"),
])
def test_the_check_can_fail(bad, expected):
    assert any(expected in p for p in problems(bad))
