"""Base of sensors: created with the scene, bound to the model when the simulation compiles."""

from __future__ import annotations

from dataclasses import MISSING

import torch

from simlab.sim import SimulationContext
from simlab.utils import configclass
from simlab.utils.unsupported import refuse_unless_default


@configclass
class SensorBaseCfg:
    class_type: type = MISSING
    prim_path: str = MISSING
    update_period: float = 0.0
    """Seconds between updates; 0 updates every physics step."""
    history_length: int = 0
    debug_vis: bool = False
    """Refused unless False: simlab's sensors draw no debug visualization."""


class SensorBase:
    def __init__(self, cfg: SensorBaseCfg, scene=None):
        cfg.validate()
        refuse_unless_default(
            f"{type(cfg).__name__}('{cfg.prim_path}')",
            "debug_vis",
            cfg.debug_vis,
            False,
            "simlab's sensors draw no debug visualization",
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

    def update(self, dt: float, force_recompute: bool = False) -> None:
        pass
