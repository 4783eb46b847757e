"""Tracking terminations: the robot's anchor or end effectors leave the clip (heights), or its anchor
tilts away from the clip's."""

from __future__ import annotations

from typing import TYPE_CHECKING

import torch

from simlab.managers import ManagerTermBase, TerminationTermCfg
from simlab.utils.errors import ConfigError

if TYPE_CHECKING:
    from simlab.envs import ManagerBasedRLEnv


def bad_anchor_pos_z_only(env: ManagerBasedRLEnv, command_name: str, threshold: float) -> torch.Tensor:
    m = env.command_manager.get_term(command_name)
    return torch.abs(m.anchor_pos_w[:, 2] - m.robot_anchor_pos_w[:, 2]) > threshold


def _gravity_z(quat: torch.Tensor) -> torch.Tensor:
    """z of the world's gravity direction (0, 0, -1) in the frame of unit quaternions (w, x, y, z):
    minus the rotation matrix's entry (2, 2), made of the quaternion alone (no constant to copy in)."""
    return 2.0 * (quat[:, 1] ** 2 + quat[:, 2] ** 2) - 1.0


def bad_anchor_ori(env: ManagerBasedRLEnv, command_name: str, threshold: float) -> torch.Tensor:
    """The z component of gravity in the clip's anchor frame and in the robot's differ by more than ``threshold``."""
    m = env.command_manager.get_term(command_name)
    return torch.abs(_gravity_z(m.anchor_quat_w) - _gravity_z(m.robot_anchor_quat_w)) > threshold


class bad_motion_body_pos_z_only(ManagerTermBase):  # noqa: N801 - a term, named like the function terms
    """One of ``body_names`` (of the command's bodies) is more than ``threshold`` above or below its clip height.

    A class so that the bodies' indices are a device tensor made once, and their names are checked
    when the env is built (a list index is copied from the host at every eager step)."""

    def __init__(self, cfg: TerminationTermCfg, env: ManagerBasedRLEnv):
        super().__init__(cfg, env)
        names = env.command_manager.get_term(cfg.params["command_name"]).cfg.body_names
        unknown = [name for name in cfg.params["body_names"] if name not in names]
        if unknown:
            raise ConfigError(f"bad_motion_body_pos_z_only: body_names {unknown} are not the command's bodies {names}.")
        self._ids = torch.tensor([names.index(name) for name in cfg.params["body_names"]], device=env.device)

    def __call__(
        self, env: ManagerBasedRLEnv, command_name: str, threshold: float, body_names: list[str]
    ) -> torch.Tensor:
        m = env.command_manager.get_term(command_name)
        error = torch.abs(m.body_pos_relative_w[:, self._ids, 2] - m.robot_body_pos_w[:, self._ids, 2])
        return torch.any(error > threshold, dim=-1)
