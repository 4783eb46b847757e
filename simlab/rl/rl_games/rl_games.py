"""rl_games adapters.

rl_games creates its env by name: ``env_configurations.register(name, {"vecenv_type": ...,
"env_creator": ...})`` names a creator, ``vecenv.register(vecenv_type, factory)`` names the
``IVecEnv`` class that drives it. :func:`register_rl_games_env` does both for a wrapped env, so the
agent config's ``env_name: rlgpu`` finds it::

    env = RlGamesVecEnvWrapper(env, rl_device, clip_obs, clip_actions)
    register_rl_games_env(env)          # "rlgpu" -> RlGamesGpuEnv -> env

Observations are clipped to ``[-clip_obs, clip_obs]``; the action space is ``[-clip_actions,
clip_actions]`` (rl_games clamps its Gaussian mean to [-1, 1] and rescales to these bounds).
With a "critic" observation group (or ``obs_groups={"obs": [...], "states": [...]}``) the env gives
``{"obs": ..., "states": ...}`` for rl_games' central value function.
"""

from __future__ import annotations

from typing import Any

import gymnasium as gym
import torch

from simlab.rl.utils import check_single_agent, require, stack_image_history

require("rl_games")
from rl_games.common import env_configurations, vecenv  # noqa: E402
from rl_games.common.algo_observer import AlgoObserver  # noqa: E402
from rl_games.common.ivecenv import IVecEnv  # noqa: E402

__all__ = ["RlGamesGpuEnv", "RlGamesVecEnvWrapper", "SimlabAlgoObserver", "register_rl_games_env"]


class RlGamesVecEnvWrapper(IVecEnv):
    """Wrap a single-agent simlab env for rl_games.

    Args:
        env: the env made with ``gym.make``.
        rl_device: device of the learner; observations and rewards are moved there.
        clip_obs: observation clipping bound.
        clip_actions: action clipping bound (the action space's bounds).
        obs_groups: ``{"obs": [groups for the actor], "states": [groups for the critic]}``; default:
            ``"policy"`` for the actor and ``"critic"`` for the critic when the env has that group.
    """

    def __init__(
        self,
        env: gym.Env,
        rl_device: str,
        clip_obs: float,
        clip_actions: float,
        obs_groups: dict[str, list[str]] | None = None,
    ):
        base = check_single_agent(env, "RlGamesVecEnvWrapper")
        for name, value in (("clip_obs", clip_obs), ("clip_actions", clip_actions)):
            if not value > 0:
                raise ValueError(f"{name} must be positive (use float('inf') for no clipping), got {value!r}.")
        self.env = env
        self._rl_device = rl_device
        self._clip_obs = float(clip_obs)
        self._clip_actions = float(clip_actions)
        self._sim_device = base.device
        groups_space = base.single_observation_space
        available = list(groups_space.spaces) if isinstance(groups_space, gym.spaces.Dict) else ["policy"]
        if obs_groups is None:
            obs_groups = {"obs": ["policy"]}
            if "critic" in available:
                obs_groups["states"] = ["critic"]
        unknown_keys = set(obs_groups) - {"obs", "states"}
        if unknown_keys or "obs" not in obs_groups:
            raise ValueError(f"obs_groups needs the key 'obs' (and optionally 'states'), got {list(obs_groups)}.")
        for key, groups in obs_groups.items():
            missing = [g for g in groups if g not in available]
            if missing:
                raise ValueError(f"obs_groups['{key}'] names {missing}, not groups of the env: {available}.")
        self.obs_groups = {k: list(v) for k, v in obs_groups.items()}
        self._shapes = {k: self._group_shape(groups_space, v) for k, v in self.obs_groups.items()}

    # -- spaces ----------------------------------------------------------------------------------

    @staticmethod
    def _group_shape(space: gym.Space, groups: list[str]) -> tuple[int, ...]:
        """What rl_games sees of these groups: one image group keeps its (H, W, C) shape (for its CNNs,
        which take channels last), an image history (k, H, W, C) is one image of k * C channels (as
        rsl_rl's wrapper stacks it: :func:`stack_image_history`); anything else is flattened and
        concatenated."""
        if not isinstance(space, gym.spaces.Dict):
            return (gym.spaces.flatdim(space),)
        if len(groups) == 1 and isinstance(space[groups[0]], gym.spaces.Box):
            shape = space[groups[0]].shape
            if len(shape) == 3:
                return tuple(shape)
            if len(shape) == 4:
                k, h, w, c = shape
                return (h, w, k * c)
        return (sum(gym.spaces.flatdim(space[g]) for g in groups),)

    @property
    def unwrapped(self) -> Any:
        return self.env.unwrapped

    @property
    def num_envs(self) -> int:
        return self.unwrapped.num_envs

    @property
    def device(self) -> str:
        return self._sim_device

    @property
    def observation_space(self) -> gym.spaces.Box:
        c = self._clip_obs
        return gym.spaces.Box(-c, c, shape=self._shapes["obs"])

    @property
    def state_space(self) -> gym.spaces.Box | None:
        if "states" not in self._shapes:
            return None
        c = self._clip_obs
        return gym.spaces.Box(-c, c, shape=self._shapes["states"])

    @property
    def action_space(self) -> gym.spaces.Box:
        c = self._clip_actions
        return gym.spaces.Box(-c, c, shape=(gym.spaces.flatdim(self.unwrapped.single_action_space),))

    def get_number_of_agents(self) -> int:
        return 1

    def get_env_info(self) -> dict:
        info = {"observation_space": self.observation_space, "action_space": self.action_space}
        if self.state_space is not None:
            info["state_space"] = self.state_space
        return info

    # -- stepping --------------------------------------------------------------------------------

    def seed(self, seed: int = -1) -> int:
        return self.unwrapped.seed(seed)

    def reset(self) -> torch.Tensor | dict[str, torch.Tensor]:
        obs, _ = self.env.reset()
        return self._process_obs(obs)

    def step(self, actions: torch.Tensor) -> tuple[Any, torch.Tensor, torch.Tensor, dict]:
        actions = torch.as_tensor(actions, dtype=torch.float32, device=self._sim_device)
        actions = torch.clamp(actions, -self._clip_actions, self._clip_actions)
        obs, rew, terminated, truncated, extras = self.env.step(actions)
        dones = (terminated | truncated).to(device=self._rl_device, dtype=torch.long)
        # rl_games bootstraps time-outs (value_bootstrap) from infos["time_outs"]
        if not getattr(self.unwrapped.cfg, "is_finite_horizon", False):
            extras["time_outs"] = truncated.to(device=self._rl_device)
        return self._process_obs(obs), rew.to(device=self._rl_device), dones, extras

    def close(self) -> None:
        self.env.close()

    def rl_games_input(self, obs: Any, key: str = "obs") -> torch.Tensor:
        """The env's observations of the groups of ``key`` ("obs" or "states") as rl_games takes them,
        unclipped: for training here, and for the played policy (the same images stacked the same way)."""
        if not isinstance(obs, dict):
            return obs
        n = next(iter(obs.values())).shape[0]
        parts = [stack_image_history(obs[g]).reshape(n, -1) for g in self.obs_groups[key]]
        return torch.cat(parts, dim=-1).view(n, *self._shapes[key])

    def _cat(self, obs: Any, key: str) -> torch.Tensor:
        x = torch.clamp(self.rl_games_input(obs, key), -self._clip_obs, self._clip_obs)
        return x.to(device=self._rl_device).clone()

    def _process_obs(self, obs: Any) -> torch.Tensor | dict[str, torch.Tensor]:
        actor = self._cat(obs, "obs")
        if "states" not in self.obs_groups:
            return actor
        return {"obs": actor, "states": self._cat(obs, "states")}


class RlGamesGpuEnv(IVecEnv):
    """The ``IVecEnv`` rl_games instantiates: it asks the registered creator for the wrapped env."""

    def __init__(self, config_name: str, num_actors: int, **kwargs):
        self.env: RlGamesVecEnvWrapper = env_configurations.configurations[config_name]["env_creator"](**kwargs)

    def step(self, actions):
        return self.env.step(actions)

    def reset(self):
        return self.env.reset()

    def get_number_of_agents(self) -> int:
        return self.env.get_number_of_agents()

    def get_env_info(self) -> dict:
        return self.env.get_env_info()

    def seed(self, seed):
        return self.env.seed(seed)

    def close(self) -> None:
        self.env.close()


def register_rl_games_env(
    env: RlGamesVecEnvWrapper, env_name: str = "rlgpu", vecenv_type: str = "SimlabRlgWrapper"
) -> None:
    """Make ``env`` the one rl_games creates for ``config.env_name == env_name``."""
    vecenv.register(vecenv_type, lambda config_name, num_actors, **kw: RlGamesGpuEnv(config_name, num_actors, **kw))
    env_configurations.register(env_name, {"vecenv_type": vecenv_type, "env_creator": lambda **kwargs: env})


class SimlabAlgoObserver(AlgoObserver):
    """Write the env's ``extras["log"]`` (reward terms, terminations) to rl_games' TensorBoard writer."""

    def __init__(self, on_epoch: Any = None):
        super().__init__()
        self._sums: dict[str, float] = {}
        self._counts: dict[str, int] = {}
        self._on_epoch = on_epoch

    def after_init(self, algo: Any) -> None:
        self.algo = algo
        self.writer = algo.writer

    def process_infos(self, infos: Any, done_indices: Any) -> None:
        if not isinstance(infos, dict) or "log" not in infos:
            return
        for key, value in infos["log"].items():
            v = float(value.float().mean()) if isinstance(value, torch.Tensor) else float(value)
            self._sums[key] = self._sums.get(key, 0.0) + v
            self._counts[key] = self._counts.get(key, 0) + 1

    def after_print_stats(self, frame: int, epoch_num: int, total_time: float) -> None:
        if self.writer is not None:
            for key, total in self._sums.items():
                self.writer.add_scalar(key if "/" in key else f"Episode/{key}", total / self._counts[key], epoch_num)
        self._sums.clear()
        self._counts.clear()
        if self._on_epoch is not None:
            self._on_epoch(frame, epoch_num, total_time)
