"""Isaac Lab 3.0's joint wrench sensor (``isaaclab.sensors.JointWrenchSensor``) on simlab's articulations.

Isaac Lab 3.0 reads the reaction wrench of an articulation's joints through a sensor, where 2.x read
``data.body_incoming_joint_wrench_b`` of the articulation (PhysX's incoming joint forces). simlab
computes that field from MuJoCo's ``cfrc_int`` (:attr:`simlab.assets.ArticulationData.body_incoming_joint_wrench_b`);
this sensor reports it per body of the articulation at ``prim_path``: ``force`` and ``torque`` in the
child body's frame about its origin, where simlab's models put each joint (3.0's only convention,
``"incoming_joint_frame"``: child-side joint frame, joint anchor as reference point). The sensor turns
on MuJoCo's post-constraint pass that the field needs, before the model compiles.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, Literal

import torch

from simlab.assets import Articulation
from simlab.utils import configclass
from simlab.utils.errors import ConfigError
from simlab.utils.string import resolve_matching_names

from ..sensor_base import SensorBase, SensorBaseCfg, prim_path_in_model


class JointWrenchSensorData:
    """Shapes use N envs and B bodies of the articulation (its ``body_names`` order)."""

    def __init__(self, sensor: JointWrenchSensor):
        self._sensor = sensor

    @property
    def force(self) -> torch.Tensor | None:
        """(N, B, 3) force each body receives through its joint [N], its frame; None before the sim starts."""
        wrench = self._sensor._wrench()
        return None if wrench is None else wrench[..., :3]

    @property
    def torque(self) -> torch.Tensor | None:
        """(N, B, 3) torque each body receives through its joint [N m], about its origin, its frame."""
        wrench = self._sensor._wrench()
        return None if wrench is None else wrench[..., 3:]

    @property
    def body_names(self) -> list[str]:
        return self._sensor.body_names


class JointWrenchSensor(SensorBase):
    cfg: JointWrenchSensorCfg

    def __init__(self, cfg: JointWrenchSensorCfg, scene: Any = None):
        if cfg.convention != "incoming_joint_frame":
            raise ConfigError(
                f"JointWrenchSensorCfg('{cfg.prim_path}').convention={cfg.convention!r}: the one convention is "
                "'incoming_joint_frame' (the child body's joint frame)."
            )
        super().__init__(cfg, scene)
        self._articulation: Articulation | None = None
        self._data = JointWrenchSensorData(self)
        self._sim.add_build_callback(_post_constraint_pass)

    @property
    def data(self) -> JointWrenchSensorData:
        return self._data

    @property
    def body_names(self) -> list[str]:
        return list(self._find_articulation().body_names) if self._is_initialized else []

    @property
    def num_bodies(self) -> int:
        return len(self.body_names)

    def find_bodies(self, name_keys: str | Sequence[str], preserve_order: bool = False) -> tuple[list[int], list[str]]:
        return resolve_matching_names(name_keys, self.body_names, preserve_order)

    def _wrench(self) -> torch.Tensor | None:
        if not self._is_initialized:
            return None
        return self._find_articulation().data.body_incoming_joint_wrench_b

    def _find_articulation(self) -> Articulation:
        """The articulation at ``prim_path``: in the scene, else among the assets the simulation holds
        (a direct env builds its sensors before it registers them with its scene)."""
        if self._articulation is None:
            path = prim_path_in_model(self.cfg.prim_path)
            found = list(self._scene.articulations.values()) if self._scene is not None else []
            found += [getattr(c, "__self__", None) for c in self._sim._on_reset]  # bound _initialize of assets
            matches = [a for a in found if isinstance(a, Articulation) and prim_path_in_model(a.cfg.prim_path) == path]
            if not matches:
                raise ConfigError(
                    f"JointWrenchSensorCfg('{self.cfg.prim_path}'): no articulation at that path; give the prim "
                    "path of an articulation of the scene, e.g. '{ENV_REGEX_NS}/Robot'."
                )
            self._articulation = matches[0]
        return self._articulation


def _post_constraint_pass(spec: Any) -> None:
    from simlab.sim.simulation_context import compute_body_interaction_forces

    compute_body_interaction_forces(spec)


@configclass
class JointWrenchSensorCfg(SensorBaseCfg):
    """A joint wrench sensor on the articulation at ``prim_path`` (e.g. ``{ENV_REGEX_NS}/Robot``)."""

    class_type: type = JointWrenchSensor
    convention: Literal["incoming_joint_frame"] = "incoming_joint_frame"
    """The frame of the reported wrench: the child body's joint frame, its joint anchor the reference point."""
