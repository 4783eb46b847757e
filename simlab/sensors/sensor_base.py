"""Base of sensors: created with the scene, bound to the model when the simulation compiles."""

from __future__ import annotations

import re
from dataclasses import MISSING

import mujoco
import torch

from simlab.sim import SimulationContext
from simlab.sim.utils import path_below_xform_group
from simlab.utils import configclass
from simlab.utils.debug_vis import DebugVisHooks
from simlab.utils.quat_order import refuse_other_order
from simlab.utils.unsupported import refuse_unless_default


@configclass
class SensorBaseCfg:
    class_type: type = MISSING
    prim_path: str = MISSING
    update_period: float = 0.0
    """Seconds between updates; 0 updates every physics step."""
    history_length: int = 0
    debug_vis: bool = False
    """Draw the sensor's markers in renders and videos; refused for a sensor that draws none."""


class SensorBase(DebugVisHooks):
    def __init__(self, cfg: SensorBaseCfg, scene=None):
        cfg.validate()
        refuse_other_order(f"{type(cfg).__name__}('{cfg.prim_path}')", cfg, "sensor")  # a simlab.v3 offset
        if not self.has_debug_vis_implementation:
            refuse_unless_default(
                f"{type(cfg).__name__}('{cfg.prim_path}')",
                "debug_vis",
                cfg.debug_vis,
                False,
                f"simlab's {type(self).__name__} draws no debug visualization",
                "Leave debug_vis=False; read the sensor's data, or draw it with simlab.markers.VisualizationMarkers"
                " (shown in env.render() and --video).",
            )
        self.cfg = cfg
        self._scene = scene
        self._sim = SimulationContext.instance()
        if self._sim is None:
            raise RuntimeError(f"Create a SimulationContext before the sensor '{cfg.prim_path}'.")
        self._is_initialized = False
        self._sim.add_compile_callback(self._on_compile)
        self._sim.add_reset_callback(self._initialize)
        if cfg.debug_vis:
            self.set_debug_vis(True)

    @property
    def device(self) -> str:
        return self._sim.device

    @property
    def num_instances(self) -> int:
        return self._sim.num_envs

    @property
    def is_initialized(self) -> bool:
        return self._is_initialized

    def _on_compile(self, model) -> None:
        pass

    def _initialize(self, sim) -> None:
        self._is_initialized = True

    def reset(self, env_ids: torch.Tensor | None = None) -> None:
        pass

    def restart(self, mask: torch.Tensor) -> None:
        """Clear what this sensor kept from the worlds the physics restarted (``InteractiveScene.restart``).
        A sensor that computes its readings when read has nothing to clear; one that accumulates them
        in its update (``ContactSensor``'s history and air times) clears them, drawing nothing."""

    def _debug_vis_simulation(self) -> SimulationContext:
        return self._sim

    def _debug_vis_ready(self) -> bool:
        return self._is_initialized

    def update(self, dt: float, force_recompute: bool = False) -> None:
        pass


_ENV_PREFIXES = ("{ENV_REGEX_NS}/", "/World/envs/env_.*/", "/World/envs/env_0/", "/World/")


def prim_path_in_model(prim_path: str) -> str:
    """``{ENV_REGEX_NS}/Robot/base`` or ``/World/envs/env_.*/Robot/base`` -> ``Robot/base`` (a regex
    over the model's names: every env is its own MuJoCo world, so the env part names nothing).
    Below ``create_prim`` groups, ``/World/Origin.*/Robot/base`` -> ``Robot/base`` too (one world per group)."""
    for prefix in _ENV_PREFIXES[:-1]:
        if prim_path.startswith(prefix):
            return prim_path[len(prefix) :]
    below_group = path_below_xform_group(prim_path)
    if below_group is not None:
        return below_group
    for prefix in _ENV_PREFIXES[-1:]:
        if prim_path.startswith(prefix):
            return prim_path[len(prefix) :]
    return prim_path.lstrip("/")


def model_body_names(model: mujoco.MjModel) -> list[str]:
    return [model.body(b).name for b in range(1, model.nbody)]


def match_body_names(names: list[str], root_names: set[str], prim_path: str) -> list[int]:
    """Indices of the ``names`` (the model's body names, world excluded) that ``prim_path`` selects
    (``{ENV_REGEX_NS}/Robot/.*``); an asset's own path (``{ENV_REGEX_NS}/Robot``, or a regex over assets,
    ``{ENV_REGEX_NS}/Obstacle.*``) selects their root bodies, those of ``root_names`` (the world's
    children) named ``Robot/...``."""
    path = prim_path_in_model(prim_path)
    entity, _, bodies = path.partition("/")
    entity_pattern = re.compile(entity)  # a regex too: ``{ENV_REGEX_NS}/Obstacle.*`` is every obstacle
    if bodies:
        pattern = re.compile(f"(?:{entity})/(?:{bodies})")
        return [i for i, name in enumerate(names) if pattern.fullmatch(name)]
    return [
        i for i, name in enumerate(names) if name in root_names and entity_pattern.fullmatch(name.partition("/")[0])
    ]


def find_sensor_bodies(model: mujoco.MjModel, prim_path: str, owner: str) -> tuple[list[int], list[str]]:
    """Ids and names of the bodies that ``prim_path`` selects (see ``match_body_names``). Raises
    naming the bodies there are."""
    names = model_body_names(model)
    roots = {model.body(b).name for b in range(1, model.nbody) if model.body_parentid[b] == 0}
    ids = [i + 1 for i in match_body_names(names, roots, prim_path)]
    if not ids:
        in_envs = any(prim_path.startswith(prefix) for prefix in _ENV_PREFIXES[:-1])
        # a path outside the envs is a create_prim group (Isaac Lab's camera tutorials) not made yet
        group = "" if in_envs else ", or create its Xform groups first (sim_utils.create_prim('<path>', 'Xform'))"
        raise ValueError(
            f"{owner} prim_path '{prim_path}' matches no body of the model; bodies in the model:"
            f" {names}. Write the path as '{{ENV_REGEX_NS}}/<asset>/<body regex>',"
            f" e.g. '{{ENV_REGEX_NS}}/Robot/base'{group}."
        )
    return ids, [model.body(b).name for b in ids]
