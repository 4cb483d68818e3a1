"""The import graph of the package: layered, without cycles (docs/extending.md).

Read from the sources with `ast` (module-level and function-level imports alike), so a lazy
import inside a function counts. The only exceptions are deprecated shims, marked on their
import line with the comment `# deprecated shim`: they keep an old entry point working
and go when the deprecation ends.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

import clearance

ROOT = Path(clearance.__file__).resolve().parent

# describe -> compile -> simulate -> store -> look: a package may import only packages of
# lower layers (and itself). Top-level modules are nodes of their own.
LAYERS = [
    {"kinds", "_kernel_cache", "layout"},  # codes, slots and layouts: no imports of ours
    {"model"},  # describe: plain dataclasses
    {"kinematics"},  # compiled floor: rotations, time functions, points and forces
    {"constraints", "contact"},  # compiled: constraint primitives, contact elements and laws
    {"compile"},  # Mechanism -> Compiled
    {"dynamics"},  # the right-hand side and the constrained solve
    {"analysis"},  # assembly, velocity analysis, inverse kinematics
    {"store"},  # Result and its channels
    {"integrate"},  # integrators, simulate()
    {"parallel"},  # the parallel-mechanism builder (legs from joint strings, mobility)
    {"<root>"},  # clearance/__init__.py: the public API (re-exports of the core)
    {"warmup"},  # compiles the kernels ahead of use (python -m clearance.warmup)
    {"io"},  # files: NetCDF, CSV, MAT
    {"nonlinear"},  # steady states, Poincare maps, spectra, Lyapunov exponents (on runs, files)
    {"mechanisms"},  # ready-made mechanisms
    {"scenario"},  # scenario files
    {"plot"},
    {"view"},  # the 3-D viewer and videos (from result files)
    {"pipeline"},
    {"sweep"},
    {"wear"},  # wear maps, Archard's law and the wear loop over runs (issue 16)
    {"cli"},
]
CORE = {
    "kinds",
    "layout",
    "model",
    "kinematics",
    "constraints",
    "contact",
    "compile",
    "dynamics",
    "analysis",
    "store",
    "integrate",
}
NOT_FROM_CORE = {
    "io",
    "plot",
    "sweep",
    "cli",
    "scenario",
    "pipeline",
    "mechanisms",
    "parallel",
    "nonlinear",
    "view",
    "wear",
}
KERNELS = {"kinematics", "constraints", "contact", "dynamics", "integrate", "compile"}


def _module_name(path: Path) -> str:
    parts = list(path.relative_to(ROOT.parent).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts = parts[:-1]
    return ".".join(parts)


def _graph() -> dict[str, set[str]]:
    """module -> modules of the package it imports (deprecated shims excluded)."""
    files = {_module_name(p): p for p in ROOT.rglob("*.py")}
    edges: dict[str, set[str]] = {}
    for mod, path in files.items():
        src = path.read_text(encoding="utf-8")
        lines = src.splitlines()
        out: set[str] = set()
        for node in ast.walk(ast.parse(src)):
            if isinstance(node, ast.Import):
                names = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
                names = [
                    f"{node.module}.{a.name}" if f"{node.module}.{a.name}" in files else node.module
                    for a in node.names
                ]
            else:
                continue
            if "deprecated shim" in lines[node.lineno - 1]:
                continue
            out.update(n for n in names if n in files and n != mod)
        edges[mod] = out
    return edges


def _package(mod: str) -> str:
    parts = mod.split(".")
    return parts[1] if len(parts) > 1 else "<root>"


def _layer(pkg: str) -> int:
    for k, layer in enumerate(LAYERS):
        if pkg in layer:
            return k
    raise AssertionError(f"package {pkg!r} is not placed in a layer of LAYERS")


FILES = {_module_name(p): p for p in ROOT.rglob("*.py")}
GRAPH = _graph()


def _cycle(edges: dict[str, set[str]]) -> list[str] | None:
    """One cycle of the directed graph, or None."""
    state: dict[str, int] = {}
    stack: list[str] = []

    def visit(n: str) -> list[str] | None:
        state[n] = 1
        stack.append(n)
        for m in sorted(edges.get(n, ())):
            if state.get(m) == 1:
                return stack[stack.index(m) :] + [m]
            if m not in state and (c := visit(m)):
                return c
        stack.pop()
        state[n] = 2
        return None

    for n in sorted(edges):
        if n not in state and (c := visit(n)):
            return c
    return None


def test_every_package_has_a_layer():
    for mod in GRAPH:
        _layer(_package(mod))


def test_no_module_cycles():
    assert _cycle(GRAPH) is None, " -> ".join(_cycle(GRAPH) or [])


def test_no_package_cycles_and_layers_respected():
    bad = []
    for mod, outs in GRAPH.items():
        a = _package(mod)
        for o in outs:
            b = _package(o)
            if a != b and _layer(b) >= _layer(a):
                bad.append(f"{mod} imports {o} ({a} -> {b} goes up or sideways)")
    assert not bad, "\n".join(bad)


@pytest.mark.parametrize("pkg", sorted(CORE))
def test_core_never_imports_the_outer_layers(pkg):
    bad = [
        (m, o)
        for m, outs in GRAPH.items()
        if _package(m) == pkg
        for o in outs
        if _package(o) in NOT_FROM_CORE
    ]
    assert not bad


def test_model_never_imports_kernels_or_numba():
    for mod, outs in GRAPH.items():
        if _package(mod) != "model":
            continue
        assert not [o for o in outs if _package(o) in KERNELS], mod
        src = FILES[mod].read_text(encoding="utf-8")
        assert "numba" not in src, f"{mod} imports numba"


def test_the_test_sees_a_cycle():
    """The checks above can fail: a planted cycle and an upward edge are found."""
    planted = {k: set(v) for k, v in GRAPH.items()}
    planted["clearance.model.bodies"].add("clearance.dynamics.rhs")
    assert _cycle({"a": {"b"}, "b": {"c"}, "c": {"a"}}) == ["a", "b", "c", "a"]
    assert _layer(_package("clearance.dynamics.rhs")) > _layer(_package("clearance.model.bodies"))
