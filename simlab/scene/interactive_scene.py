"""The interactive scene: builds one MuJoCo model from the entities of its config.

Each config field that is an asset or sensor config becomes an entity, added to the spec in
declaration order. The scene then owns the entity objects (``scene["robot"]``), the environment
origins, and the per-step calls that move data between the entities and the simulation.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import fields

import torch

import simlab.utils.math as math_utils
from simlab.assets import (
    Articulation,
    ArticulationCfg,
    AssetBaseCfg,
    RigidObject,
    RigidObjectCfg,
    RigidObjectCollection,
    RigidObjectCollectionCfg,
)
from simlab.assets.asset_base import check_asset_cfg
from simlab.sensors import SensorBase, SensorBaseCfg
from simlab.sim import SimulationContext
from simlab.terrains.terrain_importer import grid_origins
from simlab.utils.string import closest_matches
from simlab.utils.unsupported import refuse_unless_default

from .interactive_scene_cfg import InteractiveSceneCfg

ENV_NS = "/World/envs/env_0"
ENV_REGEX_NS = "/World/envs/env_.*"


def check_scene_cfg(cfg: InteractiveSceneCfg) -> None:
    """Refuse the scene settings simlab cannot honour (``lazy_sensor_update`` and ``clone_in_fabric``
    change only speed in Isaac Lab and are accepted with either value). ``replicate_physics=False``
    is accepted: every simlab env is a world of one compiled model either way, and what Isaac Lab
    needs it for, per-env ``prestartup`` randomizations (scale, color), are per-world model fields."""
    owner = type(cfg).__name__
    refuse_unless_default(
        owner,
        "filter_collisions",
        cfg.filter_collisions,
        True,
        "simlab's envs are separate MuJoCo worlds and cannot collide with each other",
        "Leave filter_collisions=True; to make objects interact, put them in the same env.",
    )


class InteractiveScene:
    def __init__(self, cfg: InteractiveSceneCfg):
        cfg.validate()
        if cfg.num_envs < 1:
            raise ValueError(f"InteractiveSceneCfg.num_envs must be at least 1, got {cfg.num_envs}")
        check_scene_cfg(cfg)
        self.cfg = cfg
        sim = SimulationContext.instance()
        if sim is None:
            raise RuntimeError("Create a SimulationContext before the InteractiveScene.")
        self.sim = sim
        sim.num_envs = cfg.num_envs
        self._terrain = self._import_terrain()
        sim.env_origins_from_terrain = self._terrain is not None
        # The origins are as large as the env count: made when first read, after sim.reset() has
        # checked that the worlds fit in memory (an env count that cannot fit is refused quickly).
        if self._terrain is None:
            sim.defer_env_origins(lambda: grid_origins(cfg.num_envs, cfg.env_spacing, sim.device))
        elif self._terrain.shares_world_frame:
            # every world holds the whole terrain: the worlds share the scene's frame
            sim.defer_env_origins(lambda: torch.zeros(cfg.num_envs, 3, device=sim.device))
        else:
            sim.defer_env_origins(lambda: self._terrain.env_origins)
        self.articulations: dict[str, Articulation] = {}
        self.rigid_objects: dict[str, RigidObject] = {}
        self.rigid_object_collections: dict[str, RigidObjectCollection] = {}
        self.sensors: dict[str, SensorBase] = {}
        self.extras: dict[str, AssetBaseCfg] = {}
        self._add_entities_from_cfg()

    # -- Isaac Lab's API --------------------------------------------------------------------------

    @property
    def num_envs(self) -> int:
        return self.cfg.num_envs

    @property
    def device(self) -> str:
        return self.sim.device

    @property
    def env_origins(self) -> torch.Tensor:
        """(num_envs, 3) positions of the environments in the world frame (on the terrain's tiles
        when the scene has a generated terrain)."""
        return self.sim.env_origins if self._terrain is None else self._terrain.env_origins

    @property
    def terrain(self):
        """The scene's ``TerrainImporter`` (None without a ``terrain`` field)."""
        return self._terrain

    @property
    def physics_dt(self) -> float:
        return self.sim.get_physics_dt()

    @property
    def env_ns(self) -> str:
        return "/World/envs"

    @property
    def env_regex_ns(self) -> str:
        return ENV_REGEX_NS

    def clone_environments(self, copy_from_source: bool = False) -> None:
        """Nothing to clone: every world already is a copy of the one model."""

    def filter_collisions(self, global_prim_paths: Sequence[str] | None = None) -> None:
        """Nothing to filter: environments are separate MuJoCo worlds and never collide."""

    def reset(self, env_ids: Sequence[int] | torch.Tensor | None = None) -> None:
        for entity in self._entities():
            entity.reset(env_ids)

    def restart(self, mask: torch.Tensor) -> None:
        """The physics restarted the worlds in ``mask`` (their state blew up: ``PhysicsBackend.restart``):
        every entity clears what it derived from that state there (actuator efforts and histories,
        contact histories), so that the rest of the step reads finite values until the env's reset of
        these worlds. By mask, drawing nothing: it runs every step, and a draw would shift every later one."""
        for entity in self._entities():
            entity.restart(mask)

    def write_data_to_sim(self) -> None:
        for asset in (
            *self.articulations.values(),
            *self.rigid_objects.values(),
            *self.rigid_object_collections.values(),
        ):
            asset.write_data_to_sim()

    def update(self, dt: float) -> None:
        for entity in self._entities():
            entity.update(dt)

    def get_state(self, is_relative: bool = False) -> dict[str, dict[str, dict[str, torch.Tensor]]]:
        """The state of every asset, Isaac Lab's layout: ``state["articulation"|"rigid_object"][name]``
        holds ``root_pose`` (pos, quat w-x-y-z), ``root_velocity`` (world lin, ang) and, for
        articulations, ``joint_position`` / ``joint_velocity``; besides, ``root_ang_vel_b``: the root's
        angular velocity in its own frame, as MuJoCo's free joint holds it (the world-frame one turned
        back rounds in float32). ``is_relative``: root positions from the env origins, exactly (each
        env is its own MuJoCo world centred there). ``reset_to`` puts a relative state into any env to
        the bit. Copies: later steps do not change them."""
        state: dict[str, dict] = {"articulation": {}, "deformable_object": {}, "rigid_object": {}}
        for group, assets in (("articulation", self.articulations), ("rigid_object", self.rigid_objects)):
            for name, asset in assets.items():
                root_pose = (asset.data.root_pose_env if is_relative else asset.data.root_pose_w).clone()
                entry = {
                    "root_pose": root_pose,
                    "root_velocity": asset.data.root_vel_w.clone(),
                    "root_ang_vel_b": asset.data.root_ang_vel_b.clone(),
                }
                if group == "articulation":
                    entry["joint_position"] = asset.data.joint_pos.clone()
                    entry["joint_velocity"] = asset.data.joint_vel.clone()
                state[group][name] = entry
        return state

    def reset_to(
        self,
        state: dict[str, dict[str, dict[str, torch.Tensor]]],
        env_ids: Sequence[int] | torch.Tensor | None = None,
        is_relative: bool = False,
    ) -> None:
        """Write a ``get_state`` state (one row per env of ``env_ids``) into the simulation. Roots
        welded to the world keep their pose.

        The worlds then start from exactly this state, as after an env reset (the physics backend's
        ``mark_reset``), so the same actions from it give the same states to the bit.

        Unlike Isaac Lab (whose code marks it FIXME), the joint targets are not set to the written
        joint state: an effort-driven joint with damping would then be pulled towards the recorded
        velocity, and a replay would leave the recording. The action terms set the targets they drive.
        """
        ids = torch.arange(self.num_envs, device=self.device) if env_ids is None else env_ids
        ids = torch.as_tensor(ids, device=self.device)
        for group, assets in (("articulation", self.articulations), ("rigid_object", self.rigid_objects)):
            for name, entry in state.get(group, {}).items():
                if name not in assets:
                    raise KeyError(f"The state has {group} '{name}', which this scene lacks; it has {list(assets)}.")
                asset = assets[name]
                root_pose = entry["root_pose"].to(self.device)
                if not asset.is_fixed_base:
                    write_pose = asset.write_root_pose_env_to_sim if is_relative else asset.write_root_pose_to_sim
                    write_pose(root_pose, env_ids=ids)
                    velocity = entry["root_velocity"].to(self.device)
                    if "root_ang_vel_b" in entry:  # absent from Isaac Lab's states
                        quat = root_pose[:, 3:7] if is_relative else math_utils.normalize(root_pose[:, 3:7])
                        ang_vel_b = _exact_turning(entry["root_ang_vel_b"].to(self.device), quat, velocity[:, 3:6])
                        asset.write_root_ang_vel_b_to_sim(ang_vel_b, env_ids=ids, lin_vel_w=velocity[:, :3])
                    else:
                        asset.write_root_velocity_to_sim(velocity, env_ids=ids)
                if group == "articulation":
                    pos, vel = entry["joint_position"].to(self.device), entry["joint_velocity"].to(self.device)
                    asset.write_joint_state_to_sim(pos, vel, env_ids=ids)
        self.write_data_to_sim()
        # the worlds start from exactly the state written (no warm start, no float64 digits of their
        # past), as after an env's reset: a restored state then replays bit-identically
        self.sim.physics.mark_reset(ids)

    def keys(self) -> list[str]:
        terrain = [self._terrain_name] if self._terrain is not None else []
        groups = (self.articulations, self.rigid_objects, self.rigid_object_collections, self.sensors, self.extras)
        return [*terrain, *(name for group in groups for name in group)]

    def __getitem__(self, key: str):
        if self._terrain is not None and key == self._terrain_name:
            return self._terrain
        for group in (self.articulations, self.rigid_objects, self.rigid_object_collections, self.sensors, self.extras):
            if key in group:
                return group[key]
        hint = closest_matches(key, self.keys())
        raise KeyError(
            f"Scene has no entity '{key}'" + (f" (did you mean {hint}?)" if hint else "") + f"; entities: {self.keys()}"
        )

    def __contains__(self, key: str) -> bool:
        return key in self.keys()

    def __str__(self) -> str:
        lines = [f"<InteractiveScene> {self.num_envs} envs, spacing {self.cfg.env_spacing} m, device {self.device}"]
        for kind, group in (
            ("articulation", self.articulations),
            ("rigid object", self.rigid_objects),
            ("sensor", self.sensors),
            ("extra", self.extras),
        ):
            lines += [f"  {name}: {kind} at {getattr(obj, 'cfg', obj).prim_path}" for name, obj in group.items()]
        for name, collection in self.rigid_object_collections.items():
            paths = [o.cfg.prim_path for o in collection.rigid_objects.values()]
            lines.append(f"  {name}: rigid object collection of {paths}")
        return "\n".join(lines)

    # -- building ---------------------------------------------------------------------------------

    def _entities(self):
        return (
            *self.articulations.values(),
            *self.rigid_objects.values(),
            *self.rigid_object_collections.values(),
            *self.sensors.values(),
        )

    def _import_terrain(self):
        """The terrain importer of the config's TerrainImporterCfg field, built first (as Isaac Lab
        does) because the env origins come from it."""
        from simlab.terrains import TerrainImporterCfg

        terrains = [(name, value) for name, value in self._cfg_entries() if isinstance(value, TerrainImporterCfg)]
        if len(terrains) > 1:
            raise ValueError(
                f"A scene takes one TerrainImporterCfg; {self.cfg.__class__.__name__} has {[n for n, _ in terrains]}"
            )
        if not terrains:
            return None
        name, cfg = terrains[0]
        cfg = cfg.replace(num_envs=self.cfg.num_envs, env_spacing=self.cfg.env_spacing)
        terrain = cfg.class_type(cfg, device=self.sim.device)
        self._terrain_name = name
        return terrain

    def _cfg_entries(self) -> list[tuple[str, object]]:
        """The config's attributes in order, those a subclass's ``__post_init__`` adds without
        declaring them included (Isaac Lab reads the config's ``__dict__``; its stack task adds its
        cubes that way)."""
        return [(name, value) for name, value in vars(self.cfg).items() if not name.startswith("_")]

    def _add_entities_from_cfg(self) -> None:
        base_fields = {f.name for f in fields(InteractiveSceneCfg)}
        for entry, value in self._cfg_entries():
            if entry in base_fields or value is None:
                continue
            if isinstance(value, RigidObjectCollectionCfg):
                objects = {
                    name: c.replace(prim_path=c.prim_path.format(ENV_REGEX_NS=ENV_REGEX_NS))
                    for name, c in value.rigid_objects.items()
                }
                self.rigid_object_collections[entry] = value.class_type(value.replace(rigid_objects=objects))
                continue
            if not isinstance(value, (AssetBaseCfg, SensorBaseCfg)):
                continue
            value = value.replace(prim_path=value.prim_path.format(ENV_REGEX_NS=ENV_REGEX_NS))
            if isinstance(value, ArticulationCfg):
                self.articulations[entry] = value.class_type(value)
            elif isinstance(value, RigidObjectCfg):
                self.rigid_objects[entry] = value.class_type(value)
            elif isinstance(value, SensorBaseCfg):
                self.sensors[entry] = value.class_type(value, self)
            else:
                check_asset_cfg(value)
                if value.spawn is not None:
                    value.spawn.func(
                        value.prim_path, value.spawn, translation=value.init_state.pos, orientation=value.init_state.rot
                    )
                self.extras[entry] = value


def _exact_turning(ang_vel_b: torch.Tensor, quat: torch.Tensor, ang_vel_w: torch.Tensor) -> torch.Tensor:
    """A state's ``root_ang_vel_b`` where it is its world-frame ``root_velocity`` turning (to float32
    rounding), else that turning in the root's frame: code that edits a state's ``root_velocity``,
    Isaac Lab's key for it, gets the velocity it wrote."""
    from_w = math_utils.quat_apply_inverse(quat, ang_vel_w)
    same = (ang_vel_b - from_w).norm(dim=-1, keepdim=True) <= 1e-5 * (1 + from_w.norm(dim=-1, keepdim=True))
    return torch.where(same, ang_vel_b, from_w)
