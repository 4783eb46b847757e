"""Rewards of the navigation tasks (Isaac Lab's ``navigation.mdp.rewards``)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import torch

if TYPE_CHECKING:
    from simlab.envs import ManagerBasedRLEnv


def position_command_error_tanh(env: ManagerBasedRLEnv, std: float, command_name: str) -> torch.Tensor:
    """``1 - tanh(d / std)`` of the distance ``d`` to the goal of a 2-D pose command (base frame)."""
    command = env.command_manager.get_command(command_name)
    return 1.0 - torch.tanh(torch.norm(command[:, :3], dim=1) / std)


def heading_command_error_abs(env: ManagerBasedRLEnv, command_name: str) -> torch.Tensor:
    """``|heading error|`` (rad) of a 2-D pose command."""
    return env.command_manager.get_command(command_name)[:, 3].abs()
