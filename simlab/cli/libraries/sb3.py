"""Stable-Baselines3 adapter: PPO from the task's YAML, VecNormalize, checkpoints, resume, Ctrl+C saves."""

from __future__ import annotations

import argparse
import copy
import os
import re
from typing import Any

import gymnasium as gym
import numpy as np
import torch
import torch.nn as nn

from simlab.cli.libraries.divergence import guard_optimizers
from simlab.cli.policy import ClampActions, Policy
from simlab.cli.session import check_training_settings
from simlab.rl.utils import require
from simlab.utils.errors import TrainingDivergedError
from simlab.utils.io import atomic_path

require("stable_baselines3")
from stable_baselines3 import PPO  # noqa: E402
from stable_baselines3.common.callbacks import BaseCallback, CallbackList, CheckpointCallback  # noqa: E402
from stable_baselines3.common.logger import configure as configure_logger  # noqa: E402
from stable_baselines3.common.vec_env import VecNormalize  # noqa: E402

from simlab.rl.sb3 import Sb3VecEnvWrapper, process_sb3_cfg  # noqa: E402

# rollouts between checkpoints (rsl_rl's save_interval of the same tasks)
SAVE_EVERY_ROLLOUTS = 50
_NOT_PPO_ARGS = ("n_timesteps", "policy", "seed", "normalize_input", "normalize_value", "clip_obs", "experiment_name")


def experiment_name(agent_cfg: dict, task: str) -> str:
    return agent_cfg.get("experiment_name") or task.split("/")[-1]


def configure(agent_cfg: dict, args: argparse.Namespace, env_cfg: Any) -> None:
    if args.seed is not None:
        agent_cfg["seed"] = args.seed
    agent_cfg["device"] = env_cfg.sim.device
    if getattr(args, "max_iterations", None) is not None:
        agent_cfg["n_timesteps"] = args.max_iterations * agent_cfg["n_steps"] * env_cfg.scene.num_envs
    check_training_settings(
        args,
        {f"agent.{key}": agent_cfg.get(key) for key in ("n_steps", "batch_size", "n_epochs", "n_timesteps")},
        {"agent.learning_rate": agent_cfg.get("learning_rate")},
    )
    env_cfg.seed = agent_cfg["seed"]


class _LogEnvExtras(BaseCallback):
    """Record the env's ``extras["log"]`` (reward terms, terminations) and a progress line per rollout."""

    def __init__(self):
        super().__init__()
        self._sums: dict[str, float] = {}
        self._counts: dict[str, int] = {}

    def _on_step(self) -> bool:
        log = self.locals["infos"][0].get("log") if self.locals.get("infos") else None
        for k, v in (log or {}).items():
            self._sums[k] = self._sums.get(k, 0.0) + v
            self._counts[k] = self._counts.get(k, 0) + 1
        return True

    def _on_rollout_end(self) -> None:
        for k, total in self._sums.items():
            self.logger.record(k if "/" in k else f"Episode/{k}", total / self._counts[k])
        self._sums.clear()
        self._counts.clear()


def _split_cfg(agent_cfg: dict, num_envs: int) -> tuple[dict, dict]:
    cfg = copy.deepcopy(agent_cfg)
    extra = {k: cfg.pop(k) for k in _NOT_PPO_ARGS if k in cfg}
    kwargs = process_sb3_cfg(cfg, num_envs)
    buffer = kwargs.get("n_steps", 2048) * num_envs
    if kwargs.get("batch_size", 64) > buffer:
        kwargs["batch_size"] = buffer  # fewer envs than the config was tuned for: one mini-batch
    return kwargs, extra


def _wrap(env: gym.Env, extra: dict, gamma: float) -> Any:
    venv = Sb3VecEnvWrapper(env, fast_variant=True)
    if extra.get("normalize_input") or extra.get("normalize_value"):
        venv = VecNormalize(
            venv,
            training=True,
            norm_obs=bool(extra.get("normalize_input")),
            norm_reward=bool(extra.get("normalize_value")),
            clip_obs=float(extra.get("clip_obs", 10.0)),
            gamma=gamma,
            clip_reward=np.inf,
        )
    return venv


def _vecnormalize_path(checkpoint: str) -> str:
    folder, name = os.path.split(checkpoint)
    m = re.match(r"model_(\d+)_steps\.zip$", name)
    return os.path.join(folder, f"model_vecnormalize_{m.group(1)}_steps.pkl" if m else "model_vecnormalize.pkl")


class _Checkpoints(CheckpointCallback):
    """SB3's periodic checkpoints (same names), written through ``save`` (atomic model + statistics)."""

    def __init__(self, save_freq: int, run_dir: str, save: Any):
        super().__init__(save_freq, run_dir, name_prefix="model", save_vecnormalize=True, verbose=0)
        self._save = save

    def _on_step(self) -> bool:
        if self.n_calls % self.save_freq == 0:
            self._save(self._checkpoint_path(extension="zip"))
        return True


def train(env: gym.Env, agent_cfg: dict, run_dir: str, args: argparse.Namespace, resume_path: str | None) -> None:
    num_envs = env.unwrapped.num_envs
    kwargs, extra = _split_cfg(agent_cfg, num_envs)
    venv = _wrap(env, extra, kwargs.get("gamma", 0.99))
    if resume_path:
        # PPO.load restores every hyperparameter saved with the model; the run's config (and the
        # overrides given with --checkpoint) apply instead, the network's shape excepted
        settings = {k: v for k, v in kwargs.items() if k not in ("policy_kwargs", "device", "seed")}
        model = PPO.load(resume_path, env=venv, device=kwargs.get("device", "auto"), **settings)
        stats = _vecnormalize_path(resume_path)
        if isinstance(venv, VecNormalize) and os.path.isfile(stats):
            loaded = VecNormalize.load(stats, venv.venv)
            venv.obs_rms, venv.ret_rms = loaded.obs_rms, loaded.ret_rms
        print(f"[simlab] Resumed from {resume_path} at {model.num_timesteps} steps")
    else:
        model = PPO(extra.get("policy", "MlpPolicy"), venv, verbose=0, seed=extra.get("seed"), **kwargs)
    model.set_logger(configure_logger(run_dir, ["tensorboard"]))

    def save(path: str) -> None:
        with atomic_path(path, suffix=".zip") as tmp:
            model.save(tmp)
        if isinstance(venv, VecNormalize):
            with atomic_path(_vecnormalize_path(path)) as tmp:
                venv.save(tmp)

    guard_optimizers([model.policy.optimizer], "agent.learning_rate")
    save_freq = max(1, kwargs.get("n_steps", 2048) * SAVE_EVERY_ROLLOUTS)
    callbacks = CallbackList([_Checkpoints(save_freq, run_dir, save), _LogEnvExtras()])

    try:
        model.learn(
            total_timesteps=int(extra["n_timesteps"]),
            callback=callbacks,
            progress_bar=True,
            reset_num_timesteps=resume_path is None,
        )
    except KeyboardInterrupt:
        path = os.path.join(run_dir, f"model_{model.num_timesteps}_steps.zip")
        save(path)
        print(f"\n[simlab] Interrupted: saved {path}")
        raise
    except TrainingDivergedError as e:
        path = os.path.join(run_dir, f"model_{model.num_timesteps}_steps.zip")
        save(path)
        raise TrainingDivergedError(f"{e} Saved the last good weights to {path}.") from None
    save(os.path.join(run_dir, f"model_{model.num_timesteps}_steps.zip"))
    save(os.path.join(run_dir, "model.zip"))


class _Sb3Actor(nn.Module):
    """VecNormalize's observation normalization + the policy's mean action."""

    def __init__(self, policy: Any, mean: np.ndarray | None, var: np.ndarray | None, clip_obs: float, eps: float):
        super().__init__()
        self.features = copy.deepcopy(policy.pi_features_extractor)
        self.mlp = copy.deepcopy(policy.mlp_extractor.policy_net)
        self.action_net = copy.deepcopy(policy.action_net)
        self.normalize = mean is not None
        dim = policy.observation_space.shape[0]
        self.register_buffer("mean", torch.as_tensor(mean if mean is not None else np.zeros(dim), dtype=torch.float32))
        self.register_buffer(
            "std", torch.sqrt(torch.as_tensor(var if var is not None else np.ones(dim), dtype=torch.float32) + eps)
        )
        self.clip_obs = float(clip_obs)

    def forward(self, obs: torch.Tensor) -> torch.Tensor:
        if self.normalize:
            obs = torch.clamp((obs - self.mean) / self.std, -self.clip_obs, self.clip_obs)
        return self.action_net(self.mlp(self.features(obs)))


def load_policy(env: gym.Env, agent_cfg: dict, checkpoint: str) -> Policy:
    device = agent_cfg.get("device", "cpu")
    model = PPO.load(checkpoint, device=device)
    mean = var = None
    clip_obs, eps = 10.0, 1e-8
    stats = _vecnormalize_path(checkpoint)
    if os.path.isfile(stats):
        import pickle

        with open(stats, "rb") as f:
            vn = pickle.load(f)
        if vn.norm_obs:
            mean, var, clip_obs, eps = vn.obs_rms.mean, vn.obs_rms.var, vn.clip_obs, vn.epsilon
    actor = _Sb3Actor(model.policy, mean, var, clip_obs, eps)
    space = model.policy.action_space
    module = ClampActions(actor, float(space.low.min()), float(space.high.max()))

    def inputs(obs: dict) -> dict[str, torch.Tensor]:
        return {"policy": obs["policy"].reshape(obs["policy"].shape[0], -1)}

    return Policy({"policy": module}, inputs, {"policy": model.policy.observation_space.shape[0]}, device=device)
