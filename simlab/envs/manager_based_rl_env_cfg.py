"""Configuration of a manager-based RL environment."""

from __future__ import annotations

from dataclasses import MISSING

from simlab.utils import configclass

from .manager_based_env_cfg import ManagerBasedEnvCfg


@configclass
class ManagerBasedRLEnvCfg(ManagerBasedEnvCfg):
    is_finite_horizon: bool = False
    """True if the task has a fixed horizon (time-outs are then terminal, not truncations, for the agent)."""
    final_observations: bool = True
    """Compute ``extras["final_obs"]`` each step: the observations the finished envs ended in, from
    which Stable-Baselines3 bootstraps time-outs. rsl_rl, skrl and rl_games do not read them; a camera
    task turns them off, since they would render every camera a second time per step."""
    episode_length_s: float = MISSING
    """Episode length in seconds: ``max_episode_length = ceil(episode_length_s / (dt * decimation))``."""
    rewards: object = MISSING
    terminations: object = MISSING
    curriculum: object | None = None
    commands: object | None = None
