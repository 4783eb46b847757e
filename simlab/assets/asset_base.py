"""The life cycle every asset shares: spawn into the spec, then bind to the compiled model.

An asset is created while the scene is built: its ``__init__`` spawns it (if ``cfg.spawn`` is set)
into the current simulation's spec. Once the simulation compiles (``sim.reset()``), ``_initialize``
looks its bodies and joints up in the model and binds its data to the backend's live tensors.
"""

from __future__ import annotations

from abc import ABC
from collections.abc import Sequence
from dataclasses import MISSING

import torch

from simlab.sim import SimulationContext
from simlab.sim.spawners import SpawnerCfg, entity_name
from simlab.utils import configclass
from simlab.utils.errors import ConfigError
from simlab.utils.quat_order import refuse_other_order
from simlab.utils.unsupported import refuse_unless_default


@configclass
class AssetBaseCfg:
    @configclass
    class InitialStateCfg:
        pos: tuple[float, float, float] = (0.0, 0.0, 0.0)
        rot: tuple[float, float, float, float] = (1.0, 0.0, 0.0, 0.0)
        """Quaternion (w, x, y, z)."""

    class_type: type | None = None
    prim_path: str = MISSING
    """``{ENV_REGEX_NS}/Name`` for a per-environment asset, ``/World/Name`` for a global one."""
    spawn: SpawnerCfg | None = None
    init_state: InitialStateCfg = InitialStateCfg()
    collision_group: int = 0
    """Isaac Lab's ``0`` (collides within its env) or ``-1`` (collides with every env). simlab's envs are
    separate worlds: a global asset (``/World/...``) is in every world, so ``-1`` holds for it and is
    refused for a per-env asset; see :func:`check_asset_cfg`."""
    debug_vis: bool = False
    """Refused unless False: simlab's assets draw no debug visualization."""


EnvIds = Sequence[int] | torch.Tensor | slice | None

_PER_ENV_PREFIXES = ("{ENV_REGEX_NS}", "/World/envs/")


def check_asset_cfg(cfg: AssetBaseCfg) -> None:
    """Refuse the asset settings simlab would otherwise accept and ignore (``collision_group``, ``debug_vis``)."""
    owner = f"{type(cfg).__name__}('{cfg.prim_path}')"
    refuse_other_order(owner, cfg, "asset")  # a simlab.v3 config (x, y, z, w) left unconverted
    if cfg.collision_group not in (0, -1):
        raise ConfigError(
            f"{owner}.collision_group={cfg.collision_group!r}: use 0 (collides within its env) or -1"
            " (collides with every env, for assets under /World such as the ground), as in Isaac Lab."
        )
    per_env = str(cfg.prim_path).startswith(_PER_ENV_PREFIXES)
    if cfg.collision_group == -1 and per_env:
        raise ConfigError(
            f"{owner}.collision_group=-1 is not supported by simlab: every env is its own MuJoCo world, so an"
            " asset inside an env cannot touch the others. Leave collision_group=0, or put an asset that every"
            " env shares under /World (e.g. /World/ground): it is then in every world."
        )
    refuse_unless_default(
        owner,
        "debug_vis",
        cfg.debug_vis,
        False,
        "simlab's assets draw no debug visualization",
        "Leave debug_vis=False; to draw frames or arrows, place simlab.markers.VisualizationMarkers yourself"
        " (they appear in env.render() and --video).",
    )


class AssetBase(ABC):
    """Spawns on construction; binds to the simulation when it compiles."""

    def __init__(self, cfg: AssetBaseCfg):
        cfg.validate()
        check_asset_cfg(cfg)
        self.cfg = cfg
        self.name = entity_name(cfg.prim_path)
        self.prefix = f"{self.name}/"
        sim = SimulationContext.instance()
        if sim is None:
            raise RuntimeError(f"Create a SimulationContext before the asset '{cfg.prim_path}'.")
        self._sim = sim
        self._is_initialized = False
        self._place_in_xform_groups(sim)
        if cfg.spawn is not None:
            cfg.spawn.func(cfg.prim_path, cfg.spawn, translation=cfg.init_state.pos, orientation=cfg.init_state.rot)
        self._on_spawned(sim)
        sim.add_compile_callback(self._on_compile)
        sim.add_reset_callback(self._initialize)

    def _place_in_xform_groups(self, sim: SimulationContext) -> None:
        """Outside a scene, an asset under ``create_prim`` groups gets one world per group (Isaac Lab's
        ``/World/Origin.*/Robot``, or ``/World/envs/env_.*/Robot`` under groups a script made itself),
        each offset by its group's translation. In a scene, the scene's env origins hold."""
        from simlab.sim.utils import xform_group_origins

        origins = xform_group_origins(self.cfg.prim_path)
        if origins is None:  # first: reading a scene's env origins would make them (see defer_env_origins)
            return
        if str(self.cfg.prim_path).startswith(_PER_ENV_PREFIXES) and sim.env_origins is not None:
            return
        origins = torch.tensor(origins, dtype=torch.float32, device=sim.device)
        if sim.model is not None:
            raise RuntimeError(f"'{self.cfg.prim_path}': create assets before sim.reset().")
        if sim.env_origins is not None and not torch.equal(sim.env_origins, origins):
            raise ValueError(
                f"'{self.cfg.prim_path}' matches {len(origins)} groups {origins.tolist()}, but the simulation already"
                f" has env origins {sim.env_origins.tolist()}: every per-group asset must sit under the same groups."
            )
        sim.num_envs, sim.env_origins = len(origins), origins

    @property
    def is_initialized(self) -> bool:
        return self._is_initialized

    @property
    def device(self) -> str:
        return self._sim.device

    @property
    def num_instances(self) -> int:
        return self._sim.num_envs

    def _on_spawned(self, sim: SimulationContext) -> None:
        """Edit the spec after spawning (actuators, joint properties)."""

    def _on_compile(self, model) -> None:
        """Edit the compiled model before the backend copies it (initial joint positions)."""

    def _initialize(self, sim: SimulationContext) -> None:
        self._is_initialized = True

    def reset(self, env_ids: EnvIds = None) -> None:
        pass

    def restart(self, mask: torch.Tensor) -> None:
        """Clear what this asset keeps derived from the state of worlds the physics restarted
        (``InteractiveScene.restart``); the state itself lives in the physics, which restarted it."""

    def write_data_to_sim(self) -> None:
        pass

    def update(self, dt: float) -> None:
        pass

    # -- index helpers ----------------------------------------------------------------------------

    def _env_index(self, env_ids: EnvIds) -> torch.Tensor | slice:
        if env_ids is None or (isinstance(env_ids, slice) and env_ids == slice(None)):
            return slice(None)
        if isinstance(env_ids, slice):
            return env_ids
        if isinstance(env_ids, torch.Tensor):
            return env_ids.to(device=self.device, dtype=torch.long) if env_ids.dtype != torch.bool else env_ids
        return self._index_tensor(env_ids)

    def _index_tensor(self, ids) -> torch.Tensor:
        """Python index lists as device tensors, cached: no host-to-device copy per step (which
        would also keep the step out of a CUDA graph)."""
        key = tuple(int(i) for i in ids)
        cache = self.__dict__.setdefault("_index_cache", {})
        if key not in cache:
            cache[key] = torch.tensor(key, dtype=torch.long, device=self.device)
        return cache[key]
