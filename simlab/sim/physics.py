"""Isaac Lab 3.0's physics backend configs (``SimulationCfg(physics=...)``), as simlab reads them.

Isaac Lab 3.0 chooses its physics with a config in ``SimulationCfg.physics``: ``NewtonCfg`` with a
solver config (``MJWarpSolverCfg``: MuJoCo Warp; Kamino, XPBD, Featherstone, VBD), ``PhysxCfg``,
``OvPhysxCfg`` or ``PhysxAutoCfg``, usually as a preset of several (``PresetCfg``; selected with
``physics=`` / ``presets=``). simlab simulates MuJoCo only:

* ``NewtonCfg(solver_cfg=MJWarpSolverCfg(...))`` is MuJoCo: its solver settings (iterations, cone,
  integrator, njmax, nconmax, ...) become the simulation's ``SimulationCfg.mujoco`` options, on either
  engine (MuJoCo C or MuJoCo Warp compile the same model options), and its ``num_substeps`` the MuJoCo
  steps of ``dt / num_substeps`` each physics step takes;
* the others are accepted and held, never used (as 2.x's ``sim.physx``): a task whose default is PhysX
  runs on simlab's MuJoCo with simlab's options. Asking for one by name (``physics=physx``, a preset
  that selects it) is refused where the name is chosen (:mod:`simlab.tasks.utils.presets`).

Module paths: ``isaaclab.physics``, ``isaaclab_newton.physics``, ``isaaclab_physx.physics`` and
``isaaclab_ov.physics`` all map here.
"""

from __future__ import annotations

from typing import Any, ClassVar

from simlab.utils import configclass
from simlab.utils.errors import ConfigError
from simlab.utils.versions import warn_once

__all__ = [
    "FeatherstoneSolverCfg",
    "KaminoPADMMSolverCfg",
    "KaminoSolverCfg",
    "MJWarpSolverCfg",
    "NewtonCfg",
    "NewtonCollisionPipelineCfg",
    "NewtonShapeCfg",
    "NewtonSolverCfg",
    "OvPhysxCfg",
    "PhysicsCfg",
    "PhysxAutoCfg",
    "PhysxCfg",
    "VBDSolverCfg",
    "XPBDSolverCfg",
    "foreign_physics",
    "mujoco_options",
]


@configclass
class PhysicsCfg:
    """Base of the physics backend configs (``isaaclab.physics.PhysicsCfg``)."""


@configclass
class NewtonSolverCfg:
    """Base of Newton's solver configs."""

    solver_type: str = "None"


@configclass
class MJWarpSolverCfg(NewtonSolverCfg):
    """MuJoCo Warp's solver settings (Isaac Lab 3.0's names and defaults); simlab sets them as the
    model's MuJoCo options on either engine."""

    solver_type: str = "mujoco_warp"
    njmax: int = 300
    nconmax: int | None = None
    iterations: int = 100
    ls_iterations: int = 50
    solver: str = "newton"
    integrator: str = "euler"
    use_mujoco_cpu: bool = False
    """True runs MuJoCo C (simlab's ``engine="mujoco"``, on the CPU)."""
    disable_contacts: bool = False
    default_actuator_gear: float | None = None
    actuator_gears: dict[str, float] | None = None
    update_data_interval: int = 1
    save_to_mjcf: str | None = None
    impratio: float = 1.0
    cone: str = "pyramidal"
    ccd_iterations: int = 35
    ls_parallel: bool = False
    use_mujoco_contacts: bool = True
    """False asks for Newton's collision pipeline, which simlab does not have: MuJoCo's collision detection
    runs instead, with a one-time note."""
    tolerance: float = 1e-6


def _any_settings(cls: type) -> type:
    """A config class of a backend simlab does not run: it takes whatever settings 3.0 code gives it
    (held in ``settings``, never read), so that files listing it among their presets load."""

    def __init__(self, **settings: Any) -> None:
        self.settings = dict(settings)

    cls.__annotations__ = {**cls.__dict__.get("__annotations__", {}), "settings": dict}
    cls.settings = None
    cls.__init__ = __init__
    return configclass(cls)


@_any_settings
class XPBDSolverCfg(NewtonSolverCfg):
    backend: ClassVar[str] = "Newton's XPBD solver"


@_any_settings
class FeatherstoneSolverCfg(NewtonSolverCfg):
    backend: ClassVar[str] = "Newton's Featherstone solver"


@_any_settings
class KaminoSolverCfg(NewtonSolverCfg):
    backend: ClassVar[str] = "Newton's Kamino solver"


KaminoPADMMSolverCfg = KaminoSolverCfg


@_any_settings
class VBDSolverCfg(NewtonSolverCfg):
    backend: ClassVar[str] = "Newton's VBD solver"


@_any_settings
class NewtonCollisionPipelineCfg:
    """Newton's own collision pipeline (``NewtonCfg.collision_cfg``): held; simlab finds contacts with MuJoCo's."""


@_any_settings
class NewtonShapeCfg:
    """Newton's default contact shape settings (``NewtonCfg.default_shape_cfg``: margin, ke, kd): held; simlab's
    contacts take the geoms' own MuJoCo solref / solimp."""


@configclass
class NewtonCfg(PhysicsCfg):
    """Newton's physics settings; with ``solver_cfg=MJWarpSolverCfg(...)`` it is MuJoCo Warp, which simlab runs."""

    num_substeps: int = 1
    debug_mode: bool = False
    use_cuda_graph: bool = True
    solver_cfg: NewtonSolverCfg = MJWarpSolverCfg()
    collision_cfg: Any = None
    default_shape_cfg: Any = None


@_any_settings
class PhysxCfg(PhysicsCfg):
    """Isaac Lab 3.0's ``isaaclab_physx.physics.PhysxCfg`` (2.x's ``sim.physx`` is :class:`simlab.sim.PhysxCfg`)."""

    backend: ClassVar[str] = "PhysX (Isaac Sim)"


@_any_settings
class OvPhysxCfg(PhysicsCfg):
    backend: ClassVar[str] = "OvPhysX"


@_any_settings
class PhysxAutoCfg(PhysicsCfg):
    backend: ClassVar[str] = "PhysX (Isaac Sim or OvPhysX)"


def foreign_physics(cfg: Any) -> str | None:
    """What backend other than MuJoCo ``cfg`` (a value of ``SimulationCfg.physics``) asks for; None when MuJoCo."""
    if isinstance(cfg, NewtonCfg):
        solver = cfg.solver_cfg
        return None if isinstance(solver, MJWarpSolverCfg) else getattr(solver, "backend", type(solver).__name__)
    if isinstance(cfg, PhysicsCfg):
        return getattr(cfg, "backend", type(cfg).__name__)
    return None


def mujoco_options(cfg: Any) -> dict[str, Any] | None:
    """The ``SimulationCfg.mujoco`` fields a MuJoCo physics config sets (None for another backend).

    ``num_substeps`` must be an int >= 1 (refused in one line otherwise); Newton's collision pipeline
    (``use_mujoco_contacts=False``) gets MuJoCo's collision detection and a one-time note."""
    if not isinstance(cfg, NewtonCfg) or foreign_physics(cfg) is not None:
        return None
    solver: MJWarpSolverCfg = cfg.solver_cfg
    if isinstance(cfg.num_substeps, bool) or not isinstance(cfg.num_substeps, int) or cfg.num_substeps < 1:
        raise ConfigError(f"NewtonCfg(num_substeps={cfg.num_substeps!r}): give an int >= 1 (MuJoCo steps per sim.dt).")
    if not solver.use_mujoco_contacts:
        warn_once(
            "MJWarpSolverCfg(use_mujoco_contacts=False) asks for Newton's collision pipeline; simlab finds contacts "
            "with MuJoCo's own collision detection."
        )
    return {
        "njmax": solver.njmax,
        "nconmax": solver.nconmax,
        "iterations": solver.iterations,
        "ls_iterations": solver.ls_iterations,
        "solver": solver.solver,
        "integrator": solver.integrator,
        "cone": solver.cone,
        "impratio": solver.impratio,
        "tolerance": solver.tolerance,
        "disable_contacts": solver.disable_contacts,
    }
