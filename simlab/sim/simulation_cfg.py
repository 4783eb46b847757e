"""Configuration of the physics simulation."""

from __future__ import annotations

from typing import TYPE_CHECKING, Literal

from simlab.utils import configclass

if TYPE_CHECKING:  # spawners import the simulation context, which imports this module
    from simlab.sim.spawners.materials import RigidBodyMaterialCfg


@configclass
class MujocoCfg:
    """MuJoCo solver options (``mjOption``) and buffer sizes; Isaac Lab's ``PhysxCfg`` counterpart."""

    integrator: Literal["euler", "rk4", "implicit", "implicitfast"] = "implicitfast"
    """``implicitfast`` integrates joint damping and PD velocity gains implicitly, as PhysX drives do."""
    solver: Literal["newton", "cg", "pgs"] = "newton"
    """MuJoCo Warp has no PGS solver: ``pgs`` only runs on the cpu backend."""
    iterations: int = 100
    ls_iterations: int = 50
    tolerance: float = 1e-8
    cone: Literal["pyramidal", "elliptic"] = "pyramidal"
    impratio: float = 1.0
    disable_contacts: bool = False
    """Skip collision detection entirely: the cheapest choice for tasks where nothing touches."""
    nconmax: int | None = None
    """Contacts per world the cuda backend reserves (None: estimated from the model)."""
    njmax: int | None = None
    """Constraint rows per world the cuda backend reserves (None: estimated from the model)."""
    num_threads: int = 0
    """Worker threads of the cpu backend (0: every core)."""


@configclass
class SimulationCfg:
    """The physics step, gravity, device and solver options of a simulation."""

    dt: float = 1.0 / 60.0
    """Physics time step in seconds."""
    render_interval: int = 1
    """Physics steps between two rendered frames when rendering while stepping."""
    device: str = "auto"
    """``"cpu"`` (MuJoCo through mjbatch), ``"cuda"`` / ``"cuda:N"`` (MuJoCo Warp), or ``"auto"``
    (the GPU when one and mujoco-warp are available, else the CPU)."""
    engine: Literal["auto", "mujoco", "mujoco_warp"] = "auto"
    """What steps the worlds: ``"auto"`` is MuJoCo (C, batched by mjbatch) on the CPU and MuJoCo Warp
    on the GPU. ``"mujoco_warp"`` on device ``"cpu"`` runs MuJoCo Warp's kernels on Warp's CPU device:
    many times slower, for checking what the GPU path computes on a machine without one."""
    gravity: tuple[float, float, float] = (0.0, 0.0, -9.81)
    mujoco: MujocoCfg = MujocoCfg()
    use_cuda_graph: bool = True
    """On the GPU, replay each whole env step as one CUDA graph when the task allows it
    (``simlab.envs.utils.cuda_graph``); False steps eagerly, kernel by kernel."""
    on_divergence: Literal["reset", "raise"] = "reset"
    """A world whose state blows up (non-finite, or restarted by MuJoCo as unstable): ``"reset"`` ends
    its episode (terminated) and counts it in ``extras["log"]["Physics/diverged"]``; ``"raise"`` stops
    with an error."""
    seed: int | None = None
    """Refused unless None: MuJoCo's physics has no random numbers. Seed the env (``env_cfg.seed``)."""
    physics_material: RigidBodyMaterialCfg | None = None
    """Isaac Lab's default material of colliders that have none: the friction of the geoms spawned
    without their own ``physics_material`` (robot files keep theirs). None keeps MuJoCo's (1.0).
    MuJoCo takes the larger friction of two touching geoms, whatever the combine mode."""
