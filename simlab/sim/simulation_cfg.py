"""Configuration of the physics simulation."""

from __future__ import annotations

from dataclasses import field
from typing import TYPE_CHECKING, Any, Literal

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
class PhysxCfg:
    """Isaac Lab's PhysX solver and GPU buffer settings, so that task configs which set them load
    unchanged (``self.sim.physx.bounce_threshold_velocity = 0.2``). They tune PhysX's own solver and
    memory, which simlab does not run, and take any value without changing a simlab simulation:
    MuJoCo's solver is set by ``SimulationCfg.mujoco`` and its buffers by ``mujoco.nconmax`` /
    ``njmax``. ``enable_ccd=True`` asks for something MuJoCo lacks and is refused."""

    solver_type: Literal[0, 1] = 1
    min_position_iteration_count: int = 1
    max_position_iteration_count: int = 255
    min_velocity_iteration_count: int = 0
    max_velocity_iteration_count: int = 255
    enable_ccd: bool = False
    enable_stabilization: bool = False
    enable_enhanced_determinism: bool = False
    bounce_threshold_velocity: float = 0.5
    friction_offset_threshold: float = 0.04
    friction_correlation_distance: float = 0.025
    gpu_max_rigid_contact_count: int = 2**23
    gpu_max_rigid_patch_count: int = 5 * 2**15
    gpu_found_lost_pairs_capacity: int = 2**21
    gpu_found_lost_aggregate_pairs_capacity: int = 2**25
    gpu_total_aggregate_pairs_capacity: int = 2**21
    gpu_collision_stack_size: int = 2**26
    gpu_heap_capacity: int = 2**26
    gpu_temp_buffer_capacity: int = 2**24
    gpu_max_num_partitions: int = 8
    gpu_max_soft_body_contacts: int = 2**20
    gpu_max_particle_contacts: int = 2**20
    solve_articulation_contact_last: bool = False


@configclass
class RenderCfg:
    """Isaac Lab's settings of Omniverse's RTX renderer, for the renders simlab draws with MuJoCo's.

    MuJoCo's renderer takes two of them: ``antialiasing_mode="Off"`` draws without multisampling
    (``visual.quality.offsamples = 0``; any other mode keeps MuJoCo's 4 samples, used by camera
    sensors), and ``enable_shadows=False`` makes no light cast shadows. The others tune ray tracing,
    DLSS and Kit settings that MuJoCo's rasterizer does not have: they are accepted and ignored, with
    a one-time note when set."""

    enable_translucency: bool | None = None
    enable_reflections: bool | None = None
    enable_global_illumination: bool | None = None
    antialiasing_mode: Literal["Off", "FXAA", "DLSS", "TAA", "DLAA"] | None = None
    enable_dlssg: bool | None = None
    enable_dl_denoiser: bool | None = None
    dlss_mode: Literal[0, 1, 2, 3] | None = None
    enable_direct_lighting: bool | None = None
    samples_per_pixel: int | None = None
    enable_shadows: bool | None = None
    enable_ambient_occlusion: bool | None = None
    carb_settings: dict | None = None
    rendering_mode: Literal["performance", "balanced", "quality"] | None = None


RENDER_SETTINGS_MAPPED = ("antialiasing_mode", "enable_shadows")
"""The :class:`RenderCfg` settings MuJoCo's renderer takes; the others are accepted and ignored."""


def _mujoco_default_material() -> RigidBodyMaterialCfg:
    from simlab.sim.spawners.materials import RigidBodyMaterialCfg  # here: the spawners import this module

    return RigidBodyMaterialCfg(static_friction=1.0, dynamic_friction=1.0)


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
    physics_material: RigidBodyMaterialCfg | None = field(default_factory=_mujoco_default_material)
    """Isaac Lab's default material of colliders that have none: the friction of the geoms spawned
    without their own ``physics_material`` (robot files keep theirs). The default is MuJoCo's own
    friction, 1.0 (Isaac Lab's is PhysX's 0.5); None leaves MuJoCo's default class alone. MuJoCo
    takes the larger friction of two touching geoms, whatever the combine mode."""
    physx: PhysxCfg = PhysxCfg()
    """PhysX's settings, accepted for Isaac Lab's configs and not used (see :class:`PhysxCfg`)."""
    disable_contact_processing: bool = False
    """Isaac Lab 2.0's switch for PhysX's contact reporting, accepted (its direct ANYmal-C, quadcopter
    and OpenAI Shadow configs set it) and not used: MuJoCo finds every contact, and the contact
    sensor reads them either way."""
    physics: Any = None
    """Isaac Lab 3.0's physics backend config (:mod:`simlab.sim.physics`), or a preset of several: a
    MuJoCo Warp config (``NewtonCfg(solver_cfg=MJWarpSolverCfg(...))``) sets :attr:`mujoco`'s options
    when the simulation starts; another backend's is held and not used; None keeps :attr:`mujoco`."""
    render: RenderCfg = RenderCfg()
    """Isaac Lab's renderer settings: antialiasing and shadows map to MuJoCo's renderer (see :class:`RenderCfg`)."""
