"""Every module of simlab imports only from its own layer or the layers below (simlab/_layers.py).

All imports count, deferred ones inside functions too; only those under ``if TYPE_CHECKING:``
(annotations, no code runs) do not. The check parses the source with ``ast``: nothing is imported.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

from simlab._layers import LAYERS, RANK, may_import

ROOT = Path(__file__).resolve().parents[1] / "simlab"


def _module_name(path: Path) -> str:
    parts = path.relative_to(ROOT.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _type_checking_nodes(tree: ast.AST) -> set[int]:
    """The ids of the import nodes under ``if TYPE_CHECKING:``."""
    skipped = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test):
            skipped |= {id(child) for stmt in node.body for child in ast.walk(stmt)}
    return skipped


def simlab_imports(path: Path, source: str | None = None) -> list[tuple[int, str]]:
    """``(line, module)`` of each simlab module ``path`` (its text, or ``source``) imports, relative ones resolved."""
    module = _module_name(path)
    package = module.split(".") if path.name == "__init__.py" else module.split(".")[:-1]
    tree = ast.parse(path.read_text() if source is None else source, filename=str(path))
    skipped = _type_checking_nodes(tree)
    found = []
    for node in ast.walk(tree):
        if id(node) in skipped:
            continue
        if isinstance(node, ast.Import):
            found += [(node.lineno, alias.name) for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package[: len(package) - node.level + 1]
                found.append((node.lineno, ".".join([*base, *([node.module] if node.module else [])])))
            else:
                found.append((node.lineno, node.module or ""))
    return [(line, name) for line, name in found if name == "simlab" or name.startswith("simlab.")]


MODULES = sorted(ROOT.rglob("*.py"))


def test_every_package_of_simlab_has_a_layer():
    packages = {p.name for p in ROOT.iterdir() if (p / "__init__.py").exists() or p.suffix == ".py"}
    packages = {p.removesuffix(".py") for p in packages} - {"__init__", "_layers"}
    assert packages <= set(RANK), f"add {sorted(packages - set(RANK))} to simlab/_layers.py LAYERS"
    assert len(RANK) == sum(len(packages) for packages, _ in LAYERS)  # each package in one row


def test_no_module_imports_from_a_higher_layer():
    upward = [
        f"{path.relative_to(ROOT.parent)}:{line} imports {name}"
        for path in MODULES
        for line, name in simlab_imports(path)
        if not may_import(_module_name(path), name)
    ]
    assert not upward, "imports from a higher layer (simlab/_layers.py):\n" + "\n".join(upward)


@pytest.mark.parametrize(
    ("source", "imported"),
    [
        ("import simlab.app\n", "simlab.app"),
        ("def f():\n    from simlab.tasks.utils import parse_env_cfg\n", "simlab.tasks.utils"),
        ("from ...markers import VisualizationMarkers\n", "simlab.markers"),
    ],
)
def test_the_check_sees_top_level_deferred_and_relative_imports(source, imported):
    path = ROOT / "sim" / "backends" / "_probe.py"  # a module there with this source (not written)
    names = [name for _, name in simlab_imports(path, source)]
    assert names == [imported] and not may_import("simlab.sim.backends._probe", imported)


def test_type_checking_imports_are_not_counted():
    source = "from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from simlab.envs import ManagerBasedEnv\n"
    tree = ast.parse(source)
    imports = [n for n in ast.walk(tree) if isinstance(n, ast.ImportFrom) and n.module == "simlab.envs"]
    assert {id(n) for n in imports} <= _type_checking_nodes(tree)


def test_higher_layers_pass_their_pieces_down_when_imported(monkeypatch):
    """The registries of simlab/_layers.py are filled by the layer above at its import."""
    from simlab.markers.visualization_markers import add_markers_to_scene
    from simlab.sim import renderer
    from simlab.utils import human_viewer

    assert add_markers_to_scene in renderer._SCENE_DECOR
    import simlab.viewer

    assert human_viewer._opener is simlab.viewer._open_for_human_render
    monkeypatch.setattr(human_viewer, "_opener", None)
    with pytest.raises(
        ValueError, match="render_mode='human' shows the env in simlab's live viewer: import simlab.viewer"
    ):
        human_viewer.open_human_viewer(object())
