"""``isaaclab.controllers`` of Isaac Lab 3.0: simlab's differential IK controller, quaternions (x, y, z, w).

The poses 3.0 code gives the controller (an absolute pose command's ``qx, qy, qz, qw``, the body's
``ee_quat`` in ``set_command`` and ``compute``) are reordered once, on the way in, and simlab's
controller (:mod:`simlab.controllers`, (w, x, y, z)) does the rest. Its state (``ee_quat_des``) stays
simlab's, (w, x, y, z): 3.0 code sets the target through ``set_command``. Relative commands
(``dx, dy, dz, droll, dpitch, dyaw``) carry no quaternion. The operational-space controller takes
poses in several places and is not offered here: simlab's own (:mod:`simlab.controllers`) reads
(w, x, y, z).
"""

from __future__ import annotations

from typing import Any

import torch

from simlab import controllers as _controllers
from simlab.controllers import DifferentialIKControllerCfg
from simlab.v3.utils.math import wxyz_from_xyzw

__all__ = ["DifferentialIKController", "DifferentialIKControllerCfg"]


def _wxyz(quat: torch.Tensor | None) -> torch.Tensor | None:
    return None if quat is None else wxyz_from_xyzw(quat)


class DifferentialIKController(_controllers.DifferentialIKController):
    """simlab's differential IK controller; its poses are (x, y, z, w), as Isaac Lab 3.0's."""

    def set_command(
        self, command: torch.Tensor, ee_pos: torch.Tensor | None = None, ee_quat: torch.Tensor | None = None
    ) -> None:
        absolute_pose = self.cfg.command_type == "pose" and not self.cfg.use_relative_mode
        if absolute_pose and command.ndim == 2 and command.shape[-1] == 7:  # else simlab's check refuses it
            command = torch.cat((command[:, :3], wxyz_from_xyzw(command[:, 3:7])), dim=-1)
        super().set_command(command, ee_pos, _wxyz(ee_quat))

    def compute(
        self, ee_pos: torch.Tensor, ee_quat: torch.Tensor, jacobian: torch.Tensor, joint_pos: torch.Tensor
    ) -> torch.Tensor:
        return super().compute(ee_pos, wxyz_from_xyzw(ee_quat), jacobian, joint_pos)


def __getattr__(name: str) -> Any:
    if name in ("OperationalSpaceController", "OperationalSpaceControllerCfg"):
        raise AttributeError(
            f"simlab.v3.controllers.{name}: not offered in Isaac Lab 3.0's (x, y, z, w) order; use "
            f"simlab.controllers.{name} with (w, x, y, z) poses (simlab.v3.utils.math.wxyz_from_xyzw)."
        )
    return getattr(_controllers, name)
