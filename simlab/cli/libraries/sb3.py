"""Stable-Baselines3 adapter: PPO from the task's YAML, VecNormalize, checkpoints, resume, Ctrl+C saves.

An SB3 ``.zip`` keeps its settings in a JSON ``data`` member whose non-JSON items (spaces, schedules,
the policy class) are cloudpickled: loading them could run code. Unless the user trusts the file,
those items are never unpickled by SB3: the ones the task's config gives are taken from it, the
spaces are read by an unpickler that knows only gymnasium's spaces and numpy (:func:`_safe_objects`).
VecNormalize's statistics are written as ``.npz`` arrays, read without pickle.
"""

from __future__ import annotations

import argparse
import base64
import copy
import json
import os
import pickle
import re
import zipfile
from typing import Any

import gymnasium as gym
import numpy as np
import torch
import torch.nn as nn

from simlab.cli.checkpoints import layer_mismatch
from simlab.cli.libraries.divergence import guard_optimizers
from simlab.cli.policy import ClampActions, Policy
from simlab.cli.session import check_at_least, check_training_settings
from simlab.rl.utils import require
from simlab.utils.errors import CheckpointError, TrainingDivergedError, UntrustedFileError
from simlab.utils.io import atomic_path
from simlab.utils.trust import NUMPY_GLOBALS, TRUST_HINT, restricted_loads

require("stable_baselines3")
from stable_baselines3 import PPO  # noqa: E402
from stable_baselines3.common.callbacks import BaseCallback, CallbackList, CheckpointCallback  # noqa: E402
from stable_baselines3.common.logger import configure as configure_logger  # noqa: E402
from stable_baselines3.common.running_mean_std import RunningMeanStd  # noqa: E402
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
    if agent_cfg.get("normalize_advantage", True):
        # SB3 normalizes the advantages of each mini-batch, which needs two samples (it asserts so); a
        # batch_size above the rollout's samples is fine: SB3 then takes the whole rollout as one mini-batch
        why = "SB3's PPO normalizes the advantages of each mini-batch, which needs 2 samples"
        check_at_least(args, "agent.batch_size", agent_cfg.get("batch_size"), 2, why)
        num_envs = env_cfg.scene.num_envs
        least = -(-2 // num_envs)  # n_steps x num_envs samples: at least 2
        rollout = f"{why}; a rollout holds {num_envs} envs x n_steps"
        check_at_least(args, "agent.n_steps", agent_cfg["n_steps"], least, rollout)
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


def _vecnormalize_path(checkpoint: str, ext: str = ".npz") -> str:
    """The statistics file beside ``checkpoint`` (``.npz``; ``.pkl``: SB3's pickle of older runs)."""
    folder, name = os.path.split(checkpoint)
    m = re.match(r"model_(\d+)_steps\.zip$", name)
    return os.path.join(folder, f"model_vecnormalize_{m.group(1)}_steps{ext}" if m else f"model_vecnormalize{ext}")


def save_statistics(venv: VecNormalize, path: str) -> None:
    """VecNormalize's statistics as plain arrays: ``obs/{mean,var,count}`` (``obs/<key>/...`` per key of a
    dict observation), ``ret/{mean,var,count}``, and its settings (clip_obs, clip_reward, epsilon, gamma, ...)."""
    arrays: dict[str, np.ndarray] = {}
    obs_rms = venv.obs_rms if isinstance(venv.obs_rms, dict) else {"": venv.obs_rms}
    for prefix, rms in [*(("/".join(("obs", k)).rstrip("/"), r) for k, r in obs_rms.items()), ("ret", venv.ret_rms)]:
        arrays.update({f"{prefix}/mean": rms.mean, f"{prefix}/var": rms.var, f"{prefix}/count": np.asarray(rms.count)})
    for key in ("clip_obs", "clip_reward", "epsilon", "gamma", "norm_obs", "norm_reward"):
        arrays[key] = np.asarray(getattr(venv, key))
    with atomic_path(path) as tmp, open(tmp, "wb") as f:
        np.savez(f, **arrays)


def load_statistics(checkpoint: str, trust: bool = False) -> dict[str, Any] | None:
    """The VecNormalize statistics beside ``checkpoint`` (None without any): ``{"obs": {key: rms},
    "ret": rms, "clip_obs": ..., ...}``. A pickled ``.pkl`` of SB3's own is read only if ``trust``."""
    path = _vecnormalize_path(checkpoint)
    if os.path.isfile(path):
        try:
            with np.load(path, allow_pickle=False) as data:
                arrays = {key: data[key] for key in data.files}
        except (OSError, ValueError, zipfile.BadZipFile) as e:
            raise CheckpointError(f"Cannot read the normalizer statistics '{path}': {e}.") from e
        stats: dict[str, Any] = {"obs": {}}
        for name in {k.rsplit("/", 1)[0] for k in arrays if "/" in k}:
            rms = RunningMeanStd(shape=arrays[f"{name}/mean"].shape)
            rms.mean, rms.var, rms.count = arrays[f"{name}/mean"], arrays[f"{name}/var"], float(arrays[f"{name}/count"])
            if name == "ret":
                stats["ret"] = rms
            else:
                stats["obs"][name[4:]] = rms  # "obs" -> "", "obs/<key>" -> "<key>"
        stats.update({k: v.item() for k, v in arrays.items() if "/" not in k})
        return stats
    pickled = _vecnormalize_path(checkpoint, ".pkl")
    if not os.path.isfile(pickled):
        return None
    if not trust:
        raise UntrustedFileError(
            f"Refused to load '{pickled}': SB3 pickles its normalizer statistics, and a pickle can run code; "
            f"{TRUST_HINT} (simlab writes them as .npz now)."
        )
    with open(pickled, "rb") as f:
        vn = pickle.load(f)  # the user vouches for the file
    obs = vn.obs_rms if isinstance(vn.obs_rms, dict) else {"": vn.obs_rms}
    settings = ("clip_obs", "clip_reward", "epsilon", "gamma", "norm_obs", "norm_reward")
    return {"obs": obs, "ret": vn.ret_rms, **{k: getattr(vn, k) for k in settings}}


def _use_statistics(venv: VecNormalize, stats: dict[str, Any]) -> None:
    venv.obs_rms = stats["obs"][""] if list(stats["obs"]) == [""] else stats["obs"]
    venv.ret_rms = stats["ret"]


def _space_global(module: str, name: str) -> bool:
    """What a pickled gymnasium space holds: the space classes, numpy arrays and its random generator."""
    return (
        module.startswith("gymnasium.spaces.")
        or f"{module}.{name}" in NUMPY_GLOBALS
        or module == "numpy.dtypes"
        or module in ("numpy.random._pickle", "numpy.random._pcg64", "numpy.random._mt19937")
        or (module == "numpy.random.bit_generator" and name in ("SeedSequence", "__pyx_unpickle_SeedSequence"))
    )


def _check_sizes(checkpoint: str, env: gym.Env, saved: Any, obs_dim: int, action_dim: int) -> None:
    """Refuse in one line a checkpoint whose policy takes or gives other sizes than ``env``'s (``saved``:
    the model, or the custom objects, with its ``observation_space`` and ``action_space``)."""
    get = saved.get if isinstance(saved, dict) else lambda key: getattr(saved, key, None)
    task = getattr(env.spec, "id", None) or "this task"
    for layer, space, here, axis in (
        ("mlp_extractor.policy_net.0.weight", get("observation_space"), obs_dim, "inputs"),
        ("action_net.weight", get("action_space"), action_dim, "outputs"),
    ):
        if space is not None and gym.spaces.flatdim(space) != here:
            theirs = gym.spaces.flatdim(space)
            raise CheckpointError(
                layer_mismatch(checkpoint, task, f"{layer} ({axis})", str(theirs), str(here)) + " Nothing was loaded."
            )


def _safe_objects(checkpoint: str, kwargs: dict, trust: bool) -> dict[str, Any] | None:
    """``custom_objects`` for ``PPO.load`` that leave nothing in the zip's ``data`` for cloudpickle: the
    settings the config gives come from ``kwargs``, the spaces from a restricted unpickler, the
    buffers SB3 rebuilds are None. An item it cannot replace refuses the file. With ``trust`` SB3 unpickles
    the items, but for those a shipped policy's zip keeps no pickle of (:mod:`simlab.pretrained.weights`)."""
    from stable_baselines3.common.utils import ConstantSchedule

    with zipfile.ZipFile(checkpoint) as z:
        data = json.loads(z.read("data")) if "data" in z.namelist() else {}
    given = {
        "policy_class": PPO.policy_aliases.get(kwargs.get("policy", "MlpPolicy"), PPO.policy_aliases["MlpPolicy"]),
        "policy_kwargs": kwargs.get("policy_kwargs", {}),
        "learning_rate": kwargs.get("learning_rate", 3e-4),
        "lr_schedule": ConstantSchedule(0.0),  # rebuilt from learning_rate when the model is set up
        "clip_range": kwargs.get("clip_range", 0.2),
        "clip_range_vf": kwargs.get("clip_range_vf"),
        "rollout_buffer_class": None,  # SB3 picks its buffer for the spaces
    }
    rebuilt = ("_last_obs", "_last_episode_starts", "_last_original_obs", "ep_info_buffer", "ep_success_buffer")
    objects: dict[str, Any] = {}
    for key, item in data.items():
        if not (isinstance(item, dict) and ":serialized:" in item):
            continue
        if trust and item[":serialized:"]:
            continue  # the user vouches for the file: SB3 unpickles it
        if key in given:
            objects[key] = given[key]
        elif key in rebuilt:
            objects[key] = None
        elif key in ("observation_space", "action_space"):
            raw = base64.b64decode(item[":serialized:"].encode())
            objects[key] = restricted_loads(raw, _space_global, f"the {key} of '{checkpoint}'")
        else:
            raise UntrustedFileError(
                f"Refused to load '{checkpoint}': its '{key}' is pickled code or data; {TRUST_HINT}."
            )
    return objects if objects or not trust else None


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
        trust = getattr(args, "trust_checkpoint", False)
        objects = _safe_objects(resume_path, {**kwargs, **extra}, trust)
        if objects is not None:
            _check_sizes(resume_path, env, objects, venv.observation_space.shape[0], venv.action_space.shape[0])
        model = PPO.load(resume_path, env=venv, device=kwargs.get("device", "auto"), custom_objects=objects, **settings)
        stats = load_statistics(resume_path, trust) if isinstance(venv, VecNormalize) else None
        if stats is not None:
            _use_statistics(venv, stats)
        print(f"[simlab] Resumed from {resume_path} at {model.num_timesteps} steps")
    else:
        model = PPO(extra.get("policy", "MlpPolicy"), venv, verbose=0, seed=extra.get("seed"), **kwargs)
    model.set_logger(configure_logger(run_dir, ["tensorboard"]))

    def save(path: str) -> None:
        with atomic_path(path, suffix=".zip") as tmp:
            model.save(tmp)
        if isinstance(venv, VecNormalize):
            save_statistics(venv, _vecnormalize_path(path))

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


def load_policy(env: gym.Env, agent_cfg: dict, checkpoint: str, trust: bool = False) -> Policy:
    device = agent_cfg.get("device", "cpu")
    kwargs, extra = _split_cfg(agent_cfg, env.unwrapped.num_envs)
    model = PPO.load(checkpoint, device=device, custom_objects=_safe_objects(checkpoint, {**kwargs, **extra}, trust))
    base = env.unwrapped
    obs_dim = gym.spaces.flatdim(base.single_observation_space["policy"])
    _check_sizes(checkpoint, env, model, obs_dim, gym.spaces.flatdim(base.single_action_space))
    mean = var = None
    clip_obs, eps = 10.0, 1e-8
    stats = load_statistics(checkpoint, trust)
    if stats is not None and stats["norm_obs"]:
        if list(stats["obs"]) != [""]:
            raise CheckpointError(f"'{checkpoint}': play supports flat observations; its statistics are per key.")
        rms = stats["obs"][""]
        mean, var, clip_obs, eps = rms.mean, rms.var, stats["clip_obs"], stats["epsilon"]
    actor = _Sb3Actor(model.policy, mean, var, clip_obs, eps)
    space = model.policy.action_space
    module = ClampActions(actor, float(space.low.min()), float(space.high.max()))

    def inputs(obs: dict) -> dict[str, torch.Tensor]:
        return {"policy": obs["policy"].reshape(obs["policy"].shape[0], -1)}

    return Policy({"policy": module}, inputs, {"policy": model.policy.observation_space.shape[0]}, device=device)
