"""``Sb3VecEnvWrapper``: a simlab env as a Stable-Baselines3 ``VecEnv`` (numpy in, numpy out).

SB3 expects Gymnasium's vector conventions: after an episode ends the returned observation is
already the reset one, the last real observation is in ``info["terminal_observation"]`` (taken from
the env's ``extras["final_obs"]``), ``info["TimeLimit.truncated"]`` marks time-outs (SB3 bootstraps
their value), and ``info["episode"] = {"r", "l"}`` gives the return and length for its logger.
The env's ``extras["log"]`` (reward terms, terminations) is passed in ``infos[0]["log"]``.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from typing import Any

import gymnasium as gym
import numpy as np
import torch

from simlab.rl.utils import check_single_agent, require

require("stable_baselines3")
from stable_baselines3.common.vec_env.base_vec_env import VecEnv, VecEnvIndices  # noqa: E402

__all__ = ["Sb3VecEnvWrapper", "process_sb3_cfg"]

# SB3 needs finite action bounds; unbounded actions are given these (as Isaac Lab does)
_UNBOUNDED_ACTION_LIMIT = 100.0


class Sb3VecEnvWrapper(VecEnv):
    """Wrap a single-agent simlab env for Stable-Baselines3.

    Args:
        env: the env made with ``gym.make``.
        fast_variant: fill the info dicts of finished envs only (the others are empty); False also
            copies the per-env entries of ``extras`` into every env's info, which costs time.
    """

    def __init__(self, env: gym.Env, fast_variant: bool = True):
        base = check_single_agent(env, "Sb3VecEnvWrapper")
        self.env = env
        self.fast_variant = fast_variant
        self.sim_device = base.device
        obs_space = base.single_observation_space
        if isinstance(obs_space, gym.spaces.Dict):
            if "policy" not in obs_space.spaces:
                raise ValueError(f"The env has no 'policy' observation group; groups: {list(obs_space.spaces)}.")
            obs_space = obs_space["policy"]
        action_space = base.single_action_space
        if isinstance(action_space, gym.spaces.Box) and not action_space.is_bounded("both"):
            lim = _UNBOUNDED_ACTION_LIMIT
            action_space = gym.spaces.Box(-lim, lim, shape=action_space.shape, dtype=np.float32)
        super().__init__(base.num_envs, obs_space, action_space)
        self._ep_rew = np.zeros(self.num_envs, dtype=np.float64)
        self._ep_len = np.zeros(self.num_envs, dtype=np.int64)
        self._async_actions: torch.Tensor | None = None

    @property
    def unwrapped(self) -> Any:
        return self.env.unwrapped

    def __str__(self) -> str:
        return f"<{type(self).__name__}{self.env}>"

    # -- VecEnv ----------------------------------------------------------------------------------

    def reset(self) -> np.ndarray:
        seed = self._seeds[0]
        obs, _ = self.env.reset(seed=seed)
        self._reset_seeds()
        self._ep_rew[:] = 0.0
        self._ep_len[:] = 0
        return self._to_numpy(self._policy_obs(obs))

    def step_async(self, actions: np.ndarray) -> None:
        if not isinstance(actions, torch.Tensor):
            actions = torch.as_tensor(np.asarray(actions), dtype=torch.float32)
        self._async_actions = actions.to(device=self.sim_device, dtype=torch.float32)

    def step_wait(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, list[dict]]:
        obs, rew, terminated, truncated, extras = self.env.step(self._async_actions)
        obs_np = self._to_numpy(self._policy_obs(obs))
        rew_np = self._to_numpy(rew).astype(np.float32).reshape(-1)
        term_np = self._to_numpy(terminated).astype(bool).reshape(-1)
        trunc_np = self._to_numpy(truncated).astype(bool).reshape(-1)
        dones = term_np | trunc_np
        self._ep_rew += rew_np
        self._ep_len += 1
        infos = self._infos(extras, dones, term_np, trunc_np)
        self._ep_rew[dones] = 0.0
        self._ep_len[dones] = 0
        return obs_np, rew_np, dones, infos

    def close(self) -> None:
        self.env.close()

    def get_attr(self, attr_name: str, indices: VecEnvIndices = None) -> list[Any]:
        n = len(self._get_indices(indices))
        if attr_name == "render_mode":
            return [self.env.render_mode] * n
        value = getattr(self.unwrapped, attr_name)
        if isinstance(value, torch.Tensor) and value.shape[:1] == (self.num_envs,):
            return [value[i] for i in self._get_indices(indices)]
        return [value] * n

    def set_attr(self, attr_name: str, value: Any, indices: VecEnvIndices = None) -> None:
        raise NotImplementedError("Sb3VecEnvWrapper.set_attr: set attributes on env.unwrapped (one env holds all).")

    def env_method(self, method_name: str, *method_args, indices: VecEnvIndices = None, **method_kwargs) -> list:
        if method_name == "render":
            return [self.env.render()]
        result = getattr(self.unwrapped, method_name)(*method_args, **method_kwargs)
        return [result] * len(self._get_indices(indices))

    def env_is_wrapped(self, wrapper_class: type[gym.Wrapper], indices: VecEnvIndices = None) -> list[bool]:
        wrapped, env = False, self.env
        while isinstance(env, gym.Wrapper):
            wrapped = wrapped or isinstance(env, wrapper_class)
            env = env.env
        return [wrapped] * len(self._get_indices(indices))

    def get_images(self) -> list[np.ndarray | None]:
        return [self.env.render()]

    # -- helpers ---------------------------------------------------------------------------------

    @staticmethod
    def _policy_obs(obs: Any) -> torch.Tensor:
        return obs["policy"] if isinstance(obs, dict) else obs

    @staticmethod
    def _to_numpy(x: Any) -> np.ndarray:
        if isinstance(x, torch.Tensor):
            return x.detach().cpu().numpy()
        return np.asarray(x)

    def _infos(self, extras: dict, dones: np.ndarray, term: np.ndarray, trunc: np.ndarray) -> list[dict]:
        infos: list[dict] = [{} for _ in range(self.num_envs)]
        if not self.fast_variant:
            for key, value in extras.items():
                if key in ("log", "final_obs"):
                    continue
                if isinstance(value, torch.Tensor) and value.shape[:1] == (self.num_envs,):
                    value = self._to_numpy(value)
                    for i in range(self.num_envs):
                        infos[i][key] = value[i]
                else:
                    for i in range(self.num_envs):
                        infos[i][key] = value
        done_ids = np.flatnonzero(dones)
        if done_ids.size:
            final = extras.get("final_obs")
            final_np = self._to_numpy(self._policy_obs(final)) if final is not None else None
            for i in done_ids:
                infos[i]["episode"] = {"r": float(self._ep_rew[i]), "l": int(self._ep_len[i])}
                infos[i]["TimeLimit.truncated"] = bool(trunc[i] and not term[i])
                if final_np is not None:
                    infos[i]["terminal_observation"] = final_np[i]
        if "log" in extras:
            infos[0]["log"] = {
                k: float(v.float().mean()) if isinstance(v, torch.Tensor) else float(v)
                for k, v in extras["log"].items()
            }
        return infos


_ACTIVATION = re.compile(r"^(?:torch\.)?nn\.(\w+)$")
_LINEAR_SCHEDULE = re.compile(r"^lin_([0-9.eE+-]+)$")


def _linear_schedule(initial: float) -> Callable[[float], float]:
    return lambda progress_remaining: progress_remaining * initial


def process_sb3_cfg(cfg: dict, num_envs: int) -> dict:
    """Turn an SB3 agent yaml into keyword arguments for the algorithm (a new dict).

    * ``"nn.ELU"``-style strings (e.g. ``policy_kwargs.activation_fn``) become the torch classes;
    * ``"lin_3e-4"`` for ``learning_rate`` / ``clip_range`` / ``clip_range_vf`` becomes a linear schedule;
    * ``n_minibatches`` becomes ``batch_size = n_steps * num_envs // n_minibatches`` (SB3's batch
      size counts samples over all envs).

    Keys that are not algorithm arguments (``n_timesteps``, ``policy``, ``seed``, ``normalize_input``,
    ``normalize_value``, ``clip_obs``) are kept for the caller to pop.
    """
    if not isinstance(num_envs, int) or num_envs < 1:
        raise ValueError(f"num_envs must be a positive int, got {num_envs!r}.")

    def convert(value: Any, key: str) -> Any:
        if isinstance(value, dict):
            return {k: convert(v, k) for k, v in value.items()}
        if isinstance(value, list):
            return [convert(v, key) for v in value]
        if isinstance(value, str):
            if m := _ACTIVATION.match(value):
                if not hasattr(torch.nn, m.group(1)):
                    raise ValueError(f"'{key}': torch.nn has no '{m.group(1)}'.")
                return getattr(torch.nn, m.group(1))
            if key in ("learning_rate", "clip_range", "clip_range_vf") and (m := _LINEAR_SCHEDULE.match(value)):
                return _linear_schedule(float(m.group(1)))
        return value

    out = convert(dict(cfg), "")
    if "n_minibatches" in out:
        n_mb = int(out.pop("n_minibatches"))
        out["batch_size"] = max(1, out.get("n_steps", 2048) * num_envs // n_mb)
    return out
