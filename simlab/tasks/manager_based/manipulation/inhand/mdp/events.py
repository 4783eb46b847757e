"""The in-hand task's reset event: joints drawn within (scaled) limit ranges."""

from __future__ import annotations

from typing import TYPE_CHECKING, Literal

import torch

from simlab.managers import EventTermCfg, ManagerTermBase, SceneEntityCfg
from simlab.utils.math import sample_uniform

if TYPE_CHECKING:
    from simlab.envs import ManagerBasedEnv

__all__ = ["reset_joints_within_limits_range"]

_ROBOT = SceneEntityCfg("robot")


class reset_joints_within_limits_range(ManagerTermBase):
    """Reset joints to positions and velocities drawn uniformly from per-joint ranges (Isaac Lab's term).

    ``position_range`` and ``velocity_range`` map joint-name patterns to ``(a, b)``: with
    ``operation="abs"`` the range is ``[a, b]``, with ``"scale"`` it is ``[a * lower limit, b * upper
    limit]`` (velocities: of the soft velocity limit); ``None`` keeps the limit. ``use_default_offset``
    adds the default joint state. Joints no pattern names keep their default state. Draws are made for
    every env and written where the reset mask is set.
    """

    takes_env_mask = True

    def __init__(self, cfg: EventTermCfg, env: ManagerBasedEnv):
        super().__init__(cfg, env)
        if "position_range" not in cfg.params or "velocity_range" not in cfg.params:
            raise ValueError(
                "reset_joints_within_limits_range needs the parameters 'position_range' and 'velocity_range',"
                f" got {list(cfg.params)}"
            )
        asset_cfg: SceneEntityCfg = cfg.params.get("asset_cfg", SceneEntityCfg("robot"))
        use_default_offset = cfg.params.get("use_default_offset", False)
        operation = cfg.params.get("operation", "abs")
        if operation not in ("abs", "scale"):
            raise ValueError(f"reset_joints_within_limits_range: operation must be 'abs' or 'scale', got '{operation}'")
        self._asset = env.scene[asset_cfg.name]
        data = self._asset.data
        soft_vel = data.soft_joint_vel_limits[0]
        self._pos_ids, self._pos_ranges = self._ranges(
            cfg.params["position_range"], data.soft_joint_pos_limits[0].clone(), operation,
            data.default_joint_pos[0] if use_default_offset else None,
        )  # fmt: skip
        self._vel_ids, self._vel_ranges = self._ranges(
            cfg.params["velocity_range"], torch.stack([-soft_vel, soft_vel], dim=1), operation,
            data.default_joint_vel[0] if use_default_offset else None,
        )  # fmt: skip

    def _ranges(self, spec: dict, ranges: torch.Tensor, operation: str, default: torch.Tensor | None):
        """The joint ids a spec names (a tensor on the env's device) and their (low, high) ranges."""
        ids: list[int] = []
        for pattern, (low, high) in spec.items():
            joint_ids = self._asset.find_joints(pattern)[0]
            ids.extend(joint_ids)
            for col, value in ((0, low), (1, high)):
                if value is not None:
                    ranges[joint_ids, col] = value if operation == "abs" else value * ranges[joint_ids, col]
            if default is not None:
                ranges[joint_ids] += default[joint_ids].unsqueeze(1)
        return torch.tensor(ids, dtype=torch.long, device=ranges.device), ranges[ids]

    def __call__(
        self,
        env: ManagerBasedEnv,
        env_ids: torch.Tensor,
        position_range: dict[str, tuple[float | None, float | None]],
        velocity_range: dict[str, tuple[float | None, float | None]],
        use_default_offset: bool = False,
        asset_cfg: SceneEntityCfg = _ROBOT,
        operation: Literal["abs", "scale"] = "abs",
    ) -> None:
        data, n = self._asset.data, self.num_envs
        joint_pos = data.default_joint_pos.clone()
        joint_vel = data.default_joint_vel.clone()
        if len(self._pos_ids):
            low, high = self._pos_ranges[:, 0], self._pos_ranges[:, 1]
            limits = data.soft_joint_pos_limits[0, self._pos_ids]
            drawn = sample_uniform(low, high, (n, len(self._pos_ids)), device=env.device)
            joint_pos[:, self._pos_ids] = drawn.clamp(limits[:, 0], limits[:, 1])
        if len(self._vel_ids):
            low, high = self._vel_ranges[:, 0], self._vel_ranges[:, 1]
            limits = data.soft_joint_vel_limits[0, self._vel_ids]
            drawn = sample_uniform(low, high, (n, len(self._vel_ids)), device=env.device)
            joint_vel[:, self._vel_ids] = drawn.clamp(-limits, limits)
        self._asset.write_joint_state_to_sim(joint_pos, joint_vel, env_ids=env_ids)
