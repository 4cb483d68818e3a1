"""The compiled-kernel cache is keyed by the kernel sources: a change to any module a kernel
can reach starts a fresh cache (numba alone would keep stale callers of an edited callee)."""

from __future__ import annotations

from pathlib import Path

from numba.core import config

from clearance import _kernel_cache
from clearance.dynamics.rhs import rhs
from clearance.integrate.methods import METHODS, method_loop


def test_kernels_cache_under_the_source_keyed_directory():
    d = str(_kernel_cache.cache_dir())
    assert _kernel_cache.source_hash() in d
    for fn in (rhs, *(method_loop(name) for name in METHODS)):
        assert fn._cache._cache_path.startswith(d), fn
    assert config.CACHE_DIR != d  # numba's global setting was restored after the imports


def _tree(root: Path) -> None:
    for rel, text in {
        "dynamics/k.py": "x = 1\n",
        "plot/f.py": "y = 1\n",
        "pipeline.py": "z = 1\n",
    }.items():
        p = root / rel
        p.parent.mkdir(parents=True, exist_ok=True)
        p.write_text(text)


def test_hash_follows_kernel_sources_only(tmp_path):
    _tree(tmp_path)
    h0 = _kernel_cache.source_hash(tmp_path)
    (tmp_path / "plot/f.py").write_text("y = 2\n")
    (tmp_path / "pipeline.py").write_text("z = 2\n")
    assert _kernel_cache.source_hash(tmp_path) == h0  # no kernels there
    (tmp_path / "dynamics/k.py").write_text("x = 2\n")
    h1 = _kernel_cache.source_hash(tmp_path)
    assert h1 != h0
    (tmp_path / "dynamics/new.py").write_text("")
    assert _kernel_cache.source_hash(tmp_path) != h1  # a new module counts too


def test_cache_location_from_the_environment(tmp_path, monkeypatch):
    monkeypatch.setenv("CLEARANCE_CACHE_DIR", str(tmp_path / "c"))
    d = _kernel_cache.cache_dir()
    assert d.parent == tmp_path / "c" and _kernel_cache.source_hash() in d.name
    monkeypatch.delenv("CLEARANCE_CACHE_DIR")
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path / "n"))
    assert _kernel_cache.cache_dir().parent == tmp_path / "n"
    monkeypatch.delenv("NUMBA_CACHE_DIR")
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "x"))
    assert _kernel_cache.cache_dir().parent == tmp_path / "x" / "clearance"


def test_codegen_settings_get_their_own_cache(monkeypatch):
    """numba's cache key ignores NUMBA_BOUNDSCHECK and NUMBA_OPT: a bounds-checked suite
    must not load the unchecked kernels of an earlier run, nor leave checked ones behind."""
    from numba.core import config

    monkeypatch.setattr(config, "BOUNDSCHECK", None)
    monkeypatch.setattr(config, "OPT", 3)
    monkeypatch.setattr(config, "DEBUGINFO_DEFAULT", 0)
    plain = _kernel_cache.cache_dir()
    assert plain.name.endswith(_kernel_cache.source_hash())
    monkeypatch.setattr(config, "BOUNDSCHECK", 1)
    checked = _kernel_cache.cache_dir()
    assert checked.name == plain.name + "-boundscheck"
    monkeypatch.setattr(config, "OPT", 2)
    assert _kernel_cache.cache_dir().name == plain.name + "-boundscheck-opt2"


def test_the_kernel_free_list_is_true():
    """No module of the kernel-free folders defines a kernel, and no kernel module imports
    one of them (numba freezes imported globals into the compiled code, so a kernel must not
    read anything the source hash does not cover)."""
    import ast

    root = _kernel_cache.PACKAGE
    free = set(_kernel_cache._NO_KERNELS)

    def is_free(rel: Path) -> bool:
        return rel.parts[0] in free

    def module_path(name: str) -> Path | None:
        parts = name.split(".")[1:]
        for cand in (Path(*parts).with_suffix(".py"), Path(*parts, "__init__.py")):
            if parts and (root / cand).exists():
                return cand
        return None

    checked = 0
    for p in root.rglob("*.py"):
        rel = p.relative_to(root)
        src = p.read_text(encoding="utf-8")
        has_kernel = "@njit" in src
        if is_free(rel):
            assert not has_kernel, f"{rel} defines a kernel but is listed as kernel-free"
            continue
        if not has_kernel:
            continue
        checked += 1
        for node in ast.walk(ast.parse(src)):
            if isinstance(node, ast.ImportFrom) and (node.module or "").startswith("clearance"):
                target = module_path(node.module)
                assert target is None or not is_free(target), (
                    f"kernel module {rel} imports {node.module}"
                )
    assert checked >= 10
