"""The package's floors (README "Architecture"): a module imports only from its floor or below."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "budget"

FLOORS = {
    "units": 1, "errors": 1, "fileio": 1, "structured": 1, "safe_text": 1, "rng": 1, "parameters": 1,
    "quadform": 1,
    "scenario": 2, "scenario_limits": 2, "scenario_errors": 2, "aiding_spec": 2, "presets": 2, "catalog": 2, "nav": 2,
    "bounds": 3, "imu": 3, "sar": 3, "check": 3, "check_text": 3, "recommend": 3,
    "motion": 4, "aiding": 4, "noise": 4,
    "mc": 5, "gap": 5, "seeds": 5, "plots": 5,
    "report": 6, "api": 6,
    "cli": 7,
}


def _imported_tops(path: Path) -> set[str]:
    """Top-level sub-packages of ``budget`` that the module at ``path`` imports."""
    rel = path.relative_to(PACKAGE).with_suffix("").parts
    package = list(rel[:-1]) if rel[-1] != "__init__" else list(rel[:-1])
    tops = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = package[:len(package) - (node.level - 1)] if node.level > 1 else package
                full = base + (node.module.split(".") if node.module else [])
                if not full:  # "from . import x" at the package root
                    full = [node.names[0].name]
            elif node.module and node.module.startswith("budget."):
                full = node.module.split(".")[1:]
            else:
                continue
            tops.add(full[0])
        elif isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name.startswith("budget."):
                    tops.add(alias.name.split(".")[1])
    return tops


def test_every_sub_package_has_a_floor():
    tops = {p.stem if p.is_file() else p.name for p in PACKAGE.iterdir()
            if (p.suffix == ".py" and p.stem != "__init__") or (p.is_dir() and (p / "__init__.py").exists())}
    assert tops <= set(FLOORS), f"give these a floor in README and here: {sorted(tops - set(FLOORS))}"


@pytest.mark.parametrize("path", sorted(PACKAGE.rglob("*.py")), ids=lambda p: str(p.relative_to(PACKAGE)))
def test_no_upward_import(path):
    rel = path.relative_to(PACKAGE).parts
    top = Path(rel[0]).stem
    if top == "__init__":
        return  # the package root serves the top-level API lazily
    upward = {t for t in _imported_tops(path) if t in FLOORS and FLOORS[t] > FLOORS[top]}
    assert not upward, f"{path.relative_to(PACKAGE)} (floor {FLOORS[top]}) imports {sorted(upward)}"
