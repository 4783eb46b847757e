"""simlab's layers: which package may import which, and why (SPEC.md, "Layering").

Lowest first. A module imports only from its own row or the rows before it (and from outside
libraries). Packages that share a row belong together and may import each other: ``simlab bench``
is a subcommand of the ``simlab`` command, the app opens the live viewer. A deferred import (inside
a function) counts like any other; an import under ``if TYPE_CHECKING:`` does not, since it names a
type for annotations and runs no code (managers annotate the env they serve).

Where a lower layer needs something from a higher one, the higher one passes it down: a callback or
a registry filled when the higher module is imported. The ones in use:

* ``simlab.sim.renderer.add_scene_decor``: ``simlab.markers`` registers its debug markers, which
  every offscreen render draws;
* ``simlab.utils.human_viewer``: ``simlab.viewer`` registers how ``render_mode="human"`` opens a
  viewer on an env;
* ``simlab.envs`` env attributes set by the learning libraries' adapters (``log_refresh_on_device``:
  the consumer of the episode logs says it reads the refresh flags itself).

``tests/test_layering.py`` parses every module of simlab and checks its imports against these rows.
"""

from __future__ import annotations

LAYERS: tuple[tuple[tuple[str, ...], str], ...] = (
    (
        ("utils", "pretrained"),
        "configclass, torch math, errors, device rules, optional imports; the shipped policies (files)",
    ),
    (
        ("sim",),
        "SimulationCfg, SimulationContext, spawners editing an MjSpec, the physics backends, offscreen renderers",
    ),
    (
        ("actuators", "terrains", "markers"),
        "actuator models, terrain generation and import, debug-visualization markers",
    ),
    (("assets",), "Articulation, RigidObject, RigidObjectCollection with their configs and data"),
    (("sensors",), "contact, ray caster, IMU, frame transformer, cameras"),
    (("scene",), "InteractiveSceneCfg, InteractiveScene: one MjSpec from the entities of a cfg"),
    (("controllers", "devices"), "differential IK, operational space; teleoperation devices and their key events"),
    (("managers",), "term configs and the managers"),
    (("envs",), "the env classes, the step runner (eager or one CUDA graph), simlab.envs.mdp"),
    (("robots",), "robot configs and their MJCF models"),
    (("rl",), "wrappers, config types and runners for the learning libraries; policy export"),
    (("tasks",), "the tasks, each with its agent configs and success criterion"),
    (("v3",), "Isaac Lab 3.0's conventions at the boundary: (x, y, z, w) quaternions in math, asset configs, envs"),
    (("viewer", "app"), "live viewers; AppLauncher"),
    (("benchmarks", "cli", "__main__"), "simlab bench; the simlab command"),
)
"""(packages under ``simlab``, what they hold), lowest first."""

RANK: dict[str, int] = {package: row for row, (packages, _) in enumerate(LAYERS) for package in packages}
"""The row of each package (``simlab.<package>``); ``simlab`` itself (its ``__init__``) is row 0."""


def may_import(importer: str, imported: str) -> bool:
    """Whether module ``importer`` (``simlab.x.y``) may import module ``imported`` (``simlab.z...``)."""
    return RANK[_package(imported)] <= RANK[_package(importer)]


def _package(module: str) -> str:
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else "utils"  # ``simlab`` itself: the lowest row
