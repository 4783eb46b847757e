"""The simulation: one MuJoCo model built from a spec, stepped in ``num_envs`` worlds by a backend.

Isaac Lab's stage is simlab's ``mujoco.MjSpec``. Spawners (ground, lights, robot files, shapes)
add to the spec of the current ``SimulationContext`` while a scene is being built; ``reset()``
compiles it once into the ``MjModel`` that every world shares, starts the backend and lets the
assets resolve their joints and bodies against it. From then on ``step()`` advances every world.
"""

from __future__ import annotations

import enum
import functools
import math
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from types import SimpleNamespace
from typing import Any

import mujoco
import torch

from simlab.utils.device import resolve_device
from simlab.utils.errors import ConfigError
from simlab.utils.startup import mark
from simlab.utils.unsupported import refuse_unless_default
from simlab.utils.versions import warn_once

from .backends import PhysicsBackend, make_backend
from .simulation_cfg import RENDER_SETTINGS_MAPPED, RenderCfg, SimulationCfg
from .stage import StageSpec

_INTEGRATORS = {
    "euler": mujoco.mjtIntegrator.mjINT_EULER,
    "rk4": mujoco.mjtIntegrator.mjINT_RK4,
    "implicit": mujoco.mjtIntegrator.mjINT_IMPLICIT,
    "implicitfast": mujoco.mjtIntegrator.mjINT_IMPLICITFAST,
}
_SOLVERS = {"newton": mujoco.mjtSolver.mjSOL_NEWTON, "cg": mujoco.mjtSolver.mjSOL_CG, "pgs": mujoco.mjtSolver.mjSOL_PGS}
_CONES = {"pyramidal": mujoco.mjtCone.mjCONE_PYRAMIDAL, "elliptic": mujoco.mjtCone.mjCONE_ELLIPTIC}


def _with_physics(cfg: SimulationCfg) -> tuple[SimulationCfg, int]:
    """``(cfg, substeps)``: ``cfg`` with Isaac Lab 3.0's ``physics`` config applied (:mod:`simlab.sim.physics`):
    a preset left unresolved takes its default; MuJoCo Warp's solver settings become ``cfg.mujoco``'s and
    its ``num_substeps`` the MuJoCo steps per ``cfg.dt``; another backend's config is held, unused, with a note."""
    from simlab.utils.presets import PresetCfg, resolve_presets

    from .physics import foreign_physics, mujoco_options

    if isinstance(cfg.physics, PresetCfg):
        cfg.physics, _ = resolve_presets(cfg.physics)
    foreign = foreign_physics(cfg.physics)
    if foreign is not None:
        warn_once(
            f"SimulationCfg.physics is {foreign}'s config ({type(cfg.physics).__name__}); simlab simulates "
            "with MuJoCo and its own options (sim.mujoco). Choose physics=newton_mjwarp for the task's MuJoCo settings."
        )
        return cfg, 1
    options = mujoco_options(cfg.physics)
    if options is None:
        return cfg, 1
    cfg.mujoco = cfg.mujoco.replace(**options)
    if cfg.physics.solver_cfg.use_mujoco_cpu and cfg.engine == "auto":
        cfg.engine = "mujoco"
    if not cfg.physics.use_cuda_graph:
        cfg.use_cuda_graph = False
    return cfg, cfg.physics.num_substeps


def _choice(table: dict, value: str, what: str):
    if value not in table:
        raise ValueError(f"Unknown MuJoCo {what} '{value}'; allowed: {sorted(table)}")
    return table[value]


class SimulationContext:
    """Owns the spec being built, the compiled model and the physics backend."""

    class RenderMode(enum.IntEnum):
        """Isaac Lab's rendering modes. simlab has no GUI and renders images offscreen on demand:
        ``PARTIAL_RENDERING``."""

        NO_GUI_OR_RENDERING = -1
        NO_RENDERING = 0
        PARTIAL_RENDERING = 1
        FULL_RENDERING = 2

    _instance: SimulationContext | None = None

    def __init__(self, cfg: SimulationCfg | None = None):
        # Isaac Lab 3.0's Newton substeps: MuJoCo steps of dt / substeps, as many per physics step
        self.cfg, self._substeps = _with_physics(cfg if cfg is not None else SimulationCfg())
        refuse_unless_default(
            "SimulationCfg",
            "seed",
            self.cfg.seed,
            None,
            "MuJoCo's physics draws no random numbers, so there is nothing in the simulation to seed",
            "Seed the environment instead: env_cfg.seed, the override env.seed=N or `simlab train --seed N`.",
        )
        refuse_unless_default(
            "SimulationCfg.physx",
            "enable_ccd",
            self.cfg.physx.enable_ccd,
            False,
            "MuJoCo has no continuous collision detection",
            "For fast, thin objects use a smaller sim.dt or thicker collision geoms.",
        )
        self.device = resolve_device(self.cfg.device)
        self.cfg.device = self.device
        if self.device.startswith("cuda"):
            torch.cuda.set_device(self.device)  # torch's current device: where tensors and graphs go
        self.spec = self._new_spec()
        self.model: mujoco.MjModel | None = None
        self.backend: PhysicsBackend | None = None
        self.num_envs = 1
        self.camera_eye: tuple[float, float, float] = (7.5, 7.5, 7.5)
        self.camera_target: tuple[float, float, float] = (0.0, 0.0, 0.0)
        self._env_origins: torch.Tensor | None = None
        self._make_env_origins: Callable[[], torch.Tensor] | None = None
        self.env_origins_from_terrain = False
        """Whether a terrain places the envs (else the origins are only a layout, which Isaac Lab
        3.0's cloner may replace by its plan's positions)."""
        self._on_build: list[Callable[[mujoco.MjSpec], None]] = []
        self._on_compile: list[Callable[[mujoco.MjModel], None]] = []
        self._on_reset: list[Callable[[SimulationContext], None]] = []
        self._on_render: list[Callable[[], None]] = []
        # Isaac Lab's named per-step callbacks: after each physics step, and at each render step
        self._physics_callbacks: dict[str, Callable[[float], None]] = {}
        self._render_step_callbacks: dict[str, Callable[[Any], None]] = {}
        self._on_clear: list[Callable[[], None]] = []
        self._step_count = 0
        # Isaac Lab's carb settings, as a plain store: what ported code sets, it reads back. simlab
        # itself reads only the entries listed in _SETTINGS_DEFAULTS (facts about this runtime).
        self._settings: dict[str, Any] = dict(_SETTINGS_DEFAULTS)
        SimulationContext._instance = self

    # -- Isaac Lab's API ------------------------------------------------------------------------

    @classmethod
    def instance(cls) -> SimulationContext | None:
        return cls._instance

    @classmethod
    def clear_instance(cls) -> None:
        if cls._instance is not None:
            cls._instance._release()
        cls._instance = None

    running_check: Callable[[], bool] | None = None
    """Set by the app (``simlab.app.launch_simulation``): what :meth:`is_running` asks."""

    def is_running(self) -> bool:
        """Isaac Lab 3.0's loop condition (``while env.sim.is_running():``): the app's answer (False once
        closed, after Ctrl+C or after ``--max_app_steps`` polls), True without an app."""
        check = SimulationContext.running_check
        return True if check is None else bool(check())

    def is_headless_or_exist_active_visualizer(self) -> bool:
        """Isaac Lab 3.0's tutorials' loop condition: :meth:`is_running` (a headless run goes on until the app
        stops it; a viewer's run until its window closes)."""
        return self.is_running()

    def get_physics_dt(self) -> float:
        return self.cfg.dt

    def get_rendering_dt(self) -> float:
        return self.cfg.dt * self.cfg.render_interval

    def set_camera_view(self, eye: Sequence[float], target: Sequence[float]) -> None:
        """Where the offscreen camera looks from and at (world frame)."""
        self.camera_eye = tuple(float(x) for x in eye)
        self.camera_target = tuple(float(x) for x in target)

    @property
    def env_origins(self) -> torch.Tensor | None:
        """(num_envs, 3) offsets of the environments in the world frame, set by the scene. Made on
        first read when the scene deferred them (``defer_env_origins``)."""
        if self._env_origins is None and self._make_env_origins is not None:
            make, self._make_env_origins = self._make_env_origins, None
            self._env_origins = make()
        return self._env_origins

    @env_origins.setter
    def env_origins(self, origins: torch.Tensor | None) -> None:
        self._env_origins, self._make_env_origins = origins, None

    def defer_env_origins(self, make: Callable[[], torch.Tensor]) -> None:
        """Make the env origins with ``make()`` when first read. A scene's origins are as large as its
        env count, so they come after ``reset()`` has checked that the worlds fit in memory."""
        self._env_origins, self._make_env_origins = None, make

    @property
    def stage(self) -> mujoco.MjSpec:
        """The spec that spawners add to (Isaac Lab's USD stage; see ``simlab.sim.utils``)."""
        return self.spec

    def set_setting(self, name: str, value: Any) -> None:
        """Store a setting under a carb-style path, e.g. ``"/isaaclab/render/rtx_sensors"``."""
        if not isinstance(name, str) or not name.startswith("/"):
            raise ValueError(f"Setting names are '/'-separated paths such as '/isaaclab/has_gui', got {name!r}.")
        self._settings[name] = value

    def get_setting(self, name: str) -> Any:
        """The value stored under ``name``, or None if it was never set (as carb answers)."""
        return self._settings.get(name)

    def stop(self) -> None:
        """Nothing runs in the background between steps, so there is nothing to stop (kept for Isaac Lab code)."""

    def is_playing(self) -> bool:
        return self.backend is not None

    def is_stopped(self) -> bool:
        return self.backend is None

    def has_gui(self) -> bool:
        return False

    def reset(self, soft: bool = False) -> None:
        """Compile the spec (first call), start the backend, and reset every world."""
        if self.backend is None:
            for build in self._on_build:
                build(self.spec)
            _apply_render_cfg(self.spec, self.cfg.render)
            self.model = self.spec.compile()
            mark("model compiled")
            geometry_qpos0 = self.model.qpos0.copy()
            for callback in self._on_compile:
                callback(self.model)  # articulations put their default joint positions in qpos0
            # ... which is where the worlds start, but MuJoCo turns hinges by qpos - qpos0: the
            # model keeps the qpos0 its geometry is written in, the backend the initial state.
            initial_qpos = self.model.qpos0.copy()
            self.model.qpos0[:] = geometry_qpos0
            if self._env_origins is None and self._make_env_origins is None:
                self.defer_env_origins(lambda: torch.zeros(self.num_envs, 3, device=self.device))
            opts = self.cfg.mujoco
            # each backend takes its own options: a thread pool on the cpu, buffer sizes on the gpu
            self.backend = make_backend(
                self.model,
                self.num_envs,
                self.device,
                engine=self.cfg.engine,
                num_threads=opts.num_threads,
                nconmax=opts.nconmax,
                njmax=opts.njmax,
                post_constraint_model=functools.partial(compile_with_post_constraint, self.spec),
            )
            mark("physics backend")  # for MuJoCo Warp: imported, initialised, model and data on the GPU
            self.backend.set_initial_qpos(initial_qpos)
            for callback in self._on_reset:
                callback(self)
        if not soft:
            self.backend.reset()
            mark("physics reset")

    def step(self, render: bool = True, forward: bool = False) -> None:
        """One physics step of every world (``mj_step``).

        Body poses, velocities and sensor data are derived quantities: asset data and sensors
        compute them when read (``PhysicsBackend.ensure_forward``). Code that reads raw MjData
        tensors of derived fields calls ``forward()`` first, or passes ``forward=True``.
        """
        self.physics.step(self._substeps, forward=forward)
        self._step_count += 1
        for callback in list(self._physics_callbacks.values()):
            callback(self.cfg.dt)

    def forward(self) -> None:
        """Recompute derived quantities (body poses, velocities, sensors) of every world now."""
        self.physics.forward()

    def render(self, mode=None) -> None:
        """Isaac Lab's render step (an env calls it every ``render_interval`` physics steps when a named
        render callback listens): runs those callbacks. Images are made offscreen, on demand
        (``env.render()``), not here."""
        event = SimpleNamespace(payload={"dt": self.get_rendering_dt()})
        for callback in list(self._render_step_callbacks.values()):
            callback(event)

    @property
    def render_mode(self) -> SimulationContext.RenderMode:
        """No GUI, images rendered offscreen on demand: ``RenderMode.PARTIAL_RENDERING``."""
        return SimulationContext.RenderMode.PARTIAL_RENDERING

    # -- simlab ---------------------------------------------------------------------------------

    @property
    def on_divergence(self) -> str:
        """What a blown-up world does: ``"reset"`` (its episode ends, counted) or ``"raise"``."""
        return self.cfg.on_divergence

    @on_divergence.setter
    def on_divergence(self, value: str) -> None:
        if value not in ("reset", "raise"):
            raise ConfigError(f"on_divergence must be 'reset' or 'raise', got {value!r}")
        self.cfg.on_divergence = value

    @property
    def can_capture_steps(self) -> bool:
        """Whether an env step on this simulation may be recorded once and replayed as a CUDA graph."""
        return self.physics.can_capture_steps

    @property
    def physics(self) -> PhysicsBackend:
        if self.backend is None:
            raise RuntimeError("The simulation is not started yet: call sim.reset() after building the scene.")
        return self.backend

    def add_build_callback(self, callback: Callable[[mujoco.MjSpec], None]) -> None:
        """Run ``callback(spec)`` right before compiling, once every entity is in the spec (sensors
        add their sites to bodies of assets declared after them)."""
        if self.model is not None:
            raise RuntimeError("The simulation is already compiled: create sensors before sim.reset().")
        self._on_build.append(callback)

    def add_compile_callback(self, callback: Callable[[mujoco.MjModel], None]) -> None:
        """Run ``callback(model)`` right after compiling, before the backend copies the model."""
        if self.model is not None:
            raise RuntimeError("The simulation is already compiled: create assets before sim.reset().")
        self._on_compile.append(callback)

    def add_reset_callback(self, callback: Callable[[SimulationContext], None]) -> None:
        """Run ``callback(sim)`` once the model is compiled (at once if it already is)."""
        self._on_reset.append(callback)
        if self.backend is not None:
            callback(self)

    def add_clear_callback(self, callback: Callable[[], None]) -> None:
        """Run ``callback()`` when this simulation is cleared (``clear_instance``, an env's ``close``):
        to release what must not outlive it, e.g. a camera's GL context."""
        self._on_clear.append(callback)

    def add_render_callback(self, name_or_callback: str | Callable[[], None], callback: Callable | None = None) -> None:
        """``add_render_callback(callback)``: run ``callback()`` before every offscreen image (debug
        visualization places its markers then). ``add_render_callback(name, callback)`` (Isaac Lab's):
        run ``callback(event)`` at every render step, ``event.payload["dt"]`` the rendering period."""
        if isinstance(name_or_callback, str):
            if callback is None:
                raise TypeError(f"add_render_callback('{name_or_callback}', callback): the callback is missing")
            self._render_step_callbacks[name_or_callback] = callback
        else:
            self._on_render.append(name_or_callback)

    def remove_render_callback(self, name: str) -> None:
        self._render_step_callbacks.pop(name, None)

    def add_physics_callback(self, name: str, callback: Callable[[float], None]) -> None:
        """Run ``callback(dt)`` after every physics step (Isaac Lab's). An env whose simulation has
        such callbacks steps eagerly (Python runs per physics step), not as a CUDA graph."""
        self._physics_callbacks[name] = callback

    def remove_physics_callback(self, name: str) -> None:
        self._physics_callbacks.pop(name, None)

    @property
    def has_step_callbacks(self) -> bool:
        """Whether named physics or render-step callbacks are registered (they need eager steps)."""
        return bool(self._physics_callbacks or self._render_step_callbacks)

    def clear_all_callbacks(self) -> None:
        """Forget the build, compile, reset, render and physics callbacks (Isaac Lab's, before
        ``clear_instance``): assets and sensors made so far are no longer set up by a later
        ``reset()``. What releases resources (``add_clear_callback``) still runs at ``clear_instance``."""
        for callbacks in (self._on_build, self._on_compile, self._on_reset, self._on_render):
            callbacks.clear()
        self._physics_callbacks.clear()
        self._render_step_callbacks.clear()

    def clear(self) -> None:
        """Empty the stage (Isaac Sim's ``clear``): a new, empty spec; what was spawned, the assets and
        sensors made on it (their callbacks) and the started simulation are gone. ``reset()`` starts
        what is built next."""
        self.clear_all_callbacks()
        self._release()
        self.backend, self.model, self.env_origins, self.num_envs = None, None, None, 1
        self.env_origins_from_terrain = False
        self.spec = self._new_spec()

    def _release(self) -> None:
        """Run what releases resources (``add_clear_callback``) once, and close the backend."""
        for callback in self._on_clear:
            callback()
        self._on_clear.clear()
        if self.backend is not None:
            self.backend.close()

    def run_render_callbacks(self) -> None:
        for callback in self._on_render:
            callback()

    def _new_spec(self) -> mujoco.MjSpec:
        cfg, opts = self.cfg, self.cfg.mujoco
        spec = StageSpec()
        spec.modelname = "simlab"
        spec.compiler.degree = False
        spec.option.timestep = cfg.dt / self._substeps
        spec.option.gravity = list(cfg.gravity)
        spec.option.integrator = _choice(_INTEGRATORS, opts.integrator, "integrator")
        spec.option.solver = _choice(_SOLVERS, opts.solver, "solver")
        spec.option.cone = _choice(_CONES, opts.cone, "cone")
        spec.option.iterations = opts.iterations
        spec.option.ls_iterations = opts.ls_iterations
        spec.option.tolerance = opts.tolerance
        spec.option.impratio = opts.impratio
        if opts.disable_contacts:
            spec.option.disableflags |= mujoco.mjtDisableBit.mjDSBL_CONTACT
        if not math.isfinite(cfg.dt) or cfg.dt <= 0:
            raise ValueError(f"SimulationCfg.dt must be a positive number of seconds, got {cfg.dt}")
        # A generous free camera distance so renders of spread-out scenes are not clipped.
        spec.visual.map.zfar = 200.0
        if cfg.physics_material is not None:  # the default class: geoms that set no friction of their own
            spec.default.geom.friction = cfg.physics_material.friction()
        return spec


POST_CONSTRAINT_TRIGGER = "simlab/contact_forces"
"""The world site whose accelerometer makes MuJoCo compute ``cfrc_ext`` and ``cfrc_int`` at every step."""


def compute_body_interaction_forces(spec: mujoco.MjSpec) -> None:
    """Make MuJoCo (C and Warp) fill ``cfrc_int`` and ``cfrc_ext`` at every forward pass.

    They come from ``mj_rnePostConstraint``, which the forward pass runs only for a model with an
    acceleration-stage sensor: one accelerometer on a world site is added (once). Without it the
    backend runs the pass when they are read (``PhysicsBackend.post_constraint``): on the GPU one
    pass instead of one in every substep's forward, on the CPU one more forward pass per read."""
    if spec.site(POST_CONSTRAINT_TRIGGER) is None:
        spec.worldbody.add_site(name=POST_CONSTRAINT_TRIGGER, group=5)
        spec.add_sensor(
            name=POST_CONSTRAINT_TRIGGER,
            type=mujoco.mjtSensor.mjSENS_ACCELEROMETER,
            objtype=mujoco.mjtObj.mjOBJ_SITE,
            objname=POST_CONSTRAINT_TRIGGER,
        )


def compile_with_post_constraint(spec: mujoco.MjSpec) -> mujoco.MjModel:
    """``spec``'s model with one more sensor, which makes its forward pass run the post-constraint
    pass: the cpu backend runs its forward pass beside the model's to give that pass on demand
    (``PhysicsBackend.post_constraint``). A frame acceleration of the world body: no site is added,
    so every other object keeps its id. Unnamed: no name of the spec's can clash with it."""
    spec = spec.copy()
    spec.add_sensor(
        type=mujoco.mjtSensor.mjSENS_FRAMELINACC,
        objtype=mujoco.mjtObj.mjOBJ_XBODY,
        objname="world",
    )
    return spec.compile()


def _apply_render_cfg(spec: mujoco.MjSpec, render: RenderCfg) -> None:
    """Isaac Lab's RTX settings that MuJoCo's renderer has; a one-time note names the ignored ones set."""
    if render.antialiasing_mode == "Off":
        spec.visual.quality.offsamples = 0
    if render.enable_shadows is False:
        for light in spec.lights:
            light.castshadow = False
    settings = render.to_dict().items()
    ignored = [name for name, value in settings if value is not None and name not in RENDER_SETTINGS_MAPPED]
    if ignored:
        warn_once(
            f"SimulationCfg.render: {', '.join(ignored)} tune Omniverse's RTX renderer; MuJoCo's renderer takes"
            " antialiasing_mode and enable_shadows, the others are accepted and ignored."
        )


# Settings whose values are facts about simlab's runtime: headless, offscreen rendering on demand.
_SETTINGS_DEFAULTS: dict[str, Any] = {
    "/isaaclab/has_gui": False,
    "/isaaclab/render/offscreen": True,
    "/physics/physxEngine": None,  # no PhysX here: MuJoCo (CPU) or MuJoCo Warp (GPU)
}


@contextmanager
def build_simulation_context(
    create_new_stage: bool = True,
    gravity_enabled: bool = True,
    device: str | None = None,
    dt: float = 0.01,
    sim_cfg: SimulationCfg | None = None,
    add_ground_plane: bool = False,
    add_lighting: bool = False,
    auto_add_lighting: bool = False,
) -> Iterator[SimulationContext]:
    """A fresh :class:`SimulationContext` for the ``with`` block, cleared when it ends (Isaac Lab's helper).

    Without ``sim_cfg`` one is made from ``dt``, ``gravity_enabled`` and ``device``; with it, only an
    explicitly given ``device`` overrides the config's. ``device=None`` picks ``"cuda:0"`` when the GPU
    backend is there and ``"cpu"`` otherwise (Isaac Lab's default is always ``"cuda:0"``). The ground
    plane goes to ``/World/defaultGroundPlane`` and the light to ``/World/defaultDomeLight`` (simlab
    has no GUI, so ``auto_add_lighting`` adds nothing). Spawn the scene inside the block, then
    ``sim.reset()`` and ``sim.step()``.
    """
    from .spawners import DomeLightCfg, GroundPlaneCfg

    if create_new_stage:
        SimulationContext.clear_instance()
    if sim_cfg is None:
        gravity = (0.0, 0.0, -9.81) if gravity_enabled else (0.0, 0.0, 0.0)
        sim_cfg = SimulationCfg(dt=dt, device=device if device is not None else "auto", gravity=gravity)
    elif device is not None:
        sim_cfg.device = device
    sim = SimulationContext(sim_cfg)
    try:
        if add_ground_plane:
            ground = GroundPlaneCfg()
            ground.func("/World/defaultGroundPlane", ground)
        if add_lighting or (auto_add_lighting and sim.get_setting("/isaaclab/has_gui")):
            light = DomeLightCfg(color=(0.1, 0.1, 0.1), intensity=10000.0)
            light.func("/World/defaultDomeLight", light, translation=(0.0, 0.0, 10.0))
        yield sim
    finally:
        sim.stop()
        if SimulationContext.instance() is sim:
            SimulationContext.clear_instance()


def current_spec() -> mujoco.MjSpec:
    """The spec that spawners add to: the current simulation's, before it is compiled."""
    sim = SimulationContext.instance()
    if sim is None:
        raise RuntimeError("No SimulationContext: create one (SimulationContext(SimulationCfg())) before spawning.")
    if sim.backend is not None:
        raise RuntimeError("The simulation is already compiled: spawn everything before sim.reset().")
    return sim.spec
