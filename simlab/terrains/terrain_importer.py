"""The terrain importer: adds the ground to the model and places the env origins on it.

With a generated terrain every MuJoCo world holds the whole terrain, so the worlds share one frame
(the simulation's per-world offsets are zero) and the env origins are points on the tiles. With a
plane each world has its own ground and the env origins are a grid, as for a scene without terrain.

Per-env state: ``terrain_levels`` and ``env_origins`` persist across episodes; only the curriculum
(``update_env_origins``) changes them, by mask or ids, so they are not reset when an episode ends.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import torch

from simlab.utils.env_mask import EnvIds, PerEnvState, env_mask, is_mask, masked_copy_

if TYPE_CHECKING:
    from .terrain_importer_cfg import TerrainImporterCfg

TERRAIN_TYPES = ("plane", "generator")


def grid_origins(num_envs: int, spacing: float, device) -> torch.Tensor:
    """Environment origins on a square-ish grid in the xy plane, centred on zero."""
    rows = math.ceil(math.sqrt(num_envs))
    cols = math.ceil(num_envs / rows)
    ii, jj = torch.meshgrid(torch.arange(rows, device=device), torch.arange(cols, device=device), indexing="ij")
    origins = torch.zeros(num_envs, 3, device=device)
    origins[:, 0] = -(ii.flatten()[:num_envs] - (rows - 1) / 2) * spacing
    origins[:, 1] = (jj.flatten()[:num_envs] - (cols - 1) / 2) * spacing
    return origins


class TerrainImporter:
    def __init__(self, cfg: TerrainImporterCfg, device: str = "cpu"):
        from simlab.sim.simulation_context import current_spec
        from simlab.sim.spawners.from_files import GroundPlaneCfg, entity_name

        cfg.validate()
        if cfg.terrain_type not in TERRAIN_TYPES:
            raise ValueError(
                f"TerrainImporterCfg.terrain_type='{cfg.terrain_type}' is not supported; use one of {TERRAIN_TYPES}"
            )
        self.cfg = cfg
        self.device = device
        self.name = entity_name(cfg.prim_path)
        self.terrain_origins: torch.Tensor | None = None
        self.terrain_generator = None
        self.flat_patches: dict[str, torch.Tensor] = {}
        """Isaac Lab's: name -> (num_rows, num_cols, num_patches, 3) flat spots on the tiles, world frame."""
        if cfg.terrain_type == "generator":
            if cfg.terrain_generator is None:
                raise ValueError("TerrainImporterCfg.terrain_type='generator' needs a terrain_generator config")
            from .mjspec_terrain import add_terrain_to_spec
            from .terrain_generator import generate_terrain

            self.terrain_generator = generate_terrain(cfg.terrain_generator)
            self.flat_patches = {name: p.to(device) for name, p in self.terrain_generator.flat_patches.items()}
            add_terrain_to_spec(
                current_spec(), self.terrain_generator, self.name, cfg.physics_material, cfg.visual_material
            )
            if cfg.use_terrain_origins:
                origins = torch.as_tensor(self.terrain_generator.terrain_origins, dtype=torch.float32, device=device)
                self.terrain_origins = origins
        else:
            ground = GroundPlaneCfg(physics_material=cfg.physics_material)
            if cfg.visual_material is not None:
                ground.color = tuple(cfg.visual_material.rgba()[:3])
            ground.func(cfg.prim_path, ground)
        if self.terrain_origins is None and cfg.env_spacing is None:
            raise ValueError("TerrainImporterCfg.env_spacing must be set to place envs on a grid")
        # The per-env state is as large as the env count: made when first read, after sim.reset()
        # has checked that the worlds fit in memory (see SimulationContext.defer_env_origins).
        self._state: PerEnvState | None = None

    @property
    def shares_world_frame(self) -> bool:
        """True when every world holds the whole terrain (envs are placed by their origins in it)."""
        return self.cfg.terrain_type == "generator"

    @property
    def state(self) -> PerEnvState:
        """The per-env buffers: ``env_origins``, and with terrain origins ``terrain_levels`` and ``terrain_types``."""
        if self._state is None:
            self._state = PerEnvState(self.cfg.num_envs, self.device)
            if self.terrain_origins is not None:
                self._configure_curriculum_origins()
            else:
                origins = grid_origins(self.cfg.num_envs, self.cfg.env_spacing, self.device)
                self._state.add("env_origins", origins, reset=None)
        return self._state

    @property
    def env_origins(self) -> torch.Tensor:
        """(num_envs, 3) positions of the envs in the world frame."""
        return self.state["env_origins"]

    @property
    def terrain_levels(self) -> torch.Tensor:
        """(num_envs,) each env's row (difficulty) on the terrain; only with terrain origins."""
        return self._curriculum_buffer("terrain_levels")

    @property
    def terrain_types(self) -> torch.Tensor:
        """(num_envs,) each env's column (kind of terrain); only with terrain origins."""
        return self._curriculum_buffer("terrain_types")

    @property
    def max_terrain_level(self) -> int:
        """The number of rows (Isaac Lab's name); only with terrain origins."""
        self._require_terrain_origins("max_terrain_level")
        return int(self.terrain_origins.shape[0])

    def _curriculum_buffer(self, name: str) -> torch.Tensor:
        self._require_terrain_origins(name)
        return self.state[name]

    def _require_terrain_origins(self, name: str) -> None:
        if self.terrain_origins is None:  # as Isaac Lab: envs on a grid have no levels
            raise AttributeError(f"TerrainImporter.{name} exists only with terrain origins (a generated terrain)")

    def _configure_curriculum_origins(self) -> None:
        """Isaac Lab's rule: each env starts on a random row up to ``max_init_terrain_level``; the
        columns (kinds) are split evenly between the envs."""
        num_rows, num_cols = self.terrain_origins.shape[:2]
        n = self.cfg.num_envs
        max_init = num_rows - 1 if self.cfg.max_init_terrain_level is None else self.cfg.max_init_terrain_level
        max_init = min(max(max_init, 0), num_rows - 1)
        levels = torch.randint(0, max_init + 1, (n,), device=self.device)
        # floor(i / (n / num_cols)) in integers: in float32 the last envs of a large n got column num_cols
        types = torch.arange(n, device=self.device) * num_cols // n
        self._state.add("terrain_levels", levels, reset=None)
        self._state.add("terrain_types", types, reset=None)
        self._state.add("env_origins", self.terrain_origins[levels, types].clone(), reset=None)

    def configure_env_origins(self, origins=None) -> None:
        """Isaac Lab's entry point: re-place the envs (on the tiles, or on a grid)."""
        if origins is not None:
            self.terrain_origins = torch.as_tensor(origins, dtype=torch.float32, device=self.device)
            self._state = None
            self.state  # noqa: B018  (re-placed now, as Isaac Lab does)

    def update_env_origins(self, env_ids: EnvIds, move_up: torch.Tensor, move_down: torch.Tensor) -> None:
        """Move the envs ``env_ids`` (ids, or a (num_envs,) bool mask with ``move_up``/``move_down`` for
        every env) one row up or down; an env past the hardest row goes to a random row (Isaac Lab's rule)."""
        if self.terrain_origins is None:
            return
        n = self.cfg.num_envs
        mask = env_mask(env_ids, n, self.device)
        if is_mask(env_ids):
            if move_up.shape != (n,) or move_down.shape != (n,):
                raise ValueError(
                    f"update_env_origins with an env mask takes move_up and move_down for every env, shape ({n},);"
                    f" got {tuple(move_up.shape)} and {tuple(move_down.shape)}"
                )
            up, down = move_up.to(self.device), move_down.to(self.device)
        else:
            # ids: move_up/down are in the order of env_ids
            all_ids = torch.arange(n, device=self.device)
            if env_ids is None or isinstance(env_ids, slice):
                ids = all_ids if env_ids is None else all_ids[env_ids]
            else:
                ids = torch.as_tensor(env_ids, dtype=torch.long, device=self.device)
            up = torch.zeros(n, dtype=torch.bool, device=self.device)
            down = torch.zeros_like(up)
            up[ids], down[ids] = move_up.to(self.device).bool(), move_down.to(self.device).bool()
        levels = self.terrain_levels + up.long() - down.long()
        random_levels = torch.randint(0, self.max_terrain_level, (n,), device=self.device)
        levels = torch.where(levels >= self.max_terrain_level, random_levels, levels.clamp(min=0))
        masked_copy_(self.terrain_levels, mask, levels)
        masked_copy_(self.env_origins, mask, self.terrain_origins[self.terrain_levels, self.terrain_types])

    def reset(self, env_ids: EnvIds = None) -> None:
        """Nothing: terrain levels persist across episodes (see the module docstring)."""

    def set_debug_vis(self, debug_vis: bool) -> bool:
        return False
