"""Configuration of a manager-based RL environment."""

from __future__ import annotations

from dataclasses import MISSING

from simlab.utils import configclass

from .manager_based_env_cfg import ManagerBasedEnvCfg


@configclass
class ManagerBasedRLEnvCfg(ManagerBasedEnvCfg):
    is_finite_horizon: bool = False
    """True if the task has a fixed horizon (time-outs are then terminal, not truncations, for the agent)."""
    episode_length_s: float = MISSING
    """Episode length in seconds: ``max_episode_length = ceil(episode_length_s / (dt * decimation))``."""
    rewards: object = MISSING
    terminations: object = MISSING
    curriculum: object | None = None
    commands: object | None = None
