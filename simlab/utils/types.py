"""Small data types shared by assets and actuators (Isaac Lab's ``isaaclab.utils.types``)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import torch

__all__ = ["ArticulationActions"]


@dataclass
class ArticulationActions:
    """Joint targets for an articulation: what an actuator model receives and returns.

    Each field is ``None`` (no command of that kind) or a tensor of shape ``(num_envs, num_joints)``
    for the joints in ``joint_indices`` (``None`` or ``slice(None)`` means all joints).
    """

    joint_positions: torch.Tensor | None = None
    joint_velocities: torch.Tensor | None = None
    joint_efforts: torch.Tensor | None = None
    joint_indices: torch.Tensor | Sequence[int] | slice | None = None
