"""rl_games adapter: the a2c_continuous agent from the task's YAML, run folders, resume, Ctrl+C saves."""

from __future__ import annotations

import argparse
import contextlib
import copy
import io
import math
import os
import tempfile
from typing import Any

import gymnasium as gym
import torch
import torch.nn as nn

from simlab.cli import distributed
from simlab.cli.libraries.divergence import guard_optimizers
from simlab.cli.libraries.progress import ProgressBar
from simlab.cli.policy import Policy
from simlab.cli.session import check_training_settings
from simlab.rl.utils import require
from simlab.utils.errors import ConfigError, TrainingDivergedError
from simlab.utils.io import atomic_torch_saves
from simlab.utils.trust import torch_load, weights_only_copy

require("rl_games")
from rl_games.torch_runner import Runner  # noqa: E402

from simlab.rl.rl_games import RlGamesVecEnvWrapper, SimlabAlgoObserver, register_rl_games_env  # noqa: E402


def experiment_name(agent_cfg: dict, task: str) -> str:
    return agent_cfg["params"]["config"]["name"]


def configure(agent_cfg: dict, args: argparse.Namespace, env_cfg: Any) -> None:
    params = agent_cfg["params"]
    config = params["config"]
    if args.seed is not None:
        params["seed"] = args.seed
    device = env_cfg.sim.device
    config["device"] = config["device_name"] = device
    config.setdefault("torch_compile", False)
    if getattr(args, "max_iterations", None) is not None:
        config["max_epochs"] = args.max_iterations
    check_training_settings(
        args,
        {
            f"agent.params.config.{key}": config.get(key)
            for key in ("horizon_length", "minibatch_size", "mini_epochs", "max_epochs")
        },
        {"agent.params.config.learning_rate": config.get("learning_rate")},
    )
    num_envs = env_cfg.scene.num_envs
    config["num_actors"] = num_envs
    if hasattr(args, "max_iterations"):  # training: play makes no mini-batches
        config["minibatch_size"] = _fitting_minibatch(config["minibatch_size"], config["horizon_length"], num_envs)
        central = config.get("central_value_config") or {}
        if "minibatch_size" in central:  # the asymmetric critic's own mini-batches of the same rollout
            central["minibatch_size"] = _fitting_minibatch(
                central["minibatch_size"], config["horizon_length"], num_envs, "central_value_config.minibatch_size"
            )
    if getattr(args, "distributed", False):
        config["multi_gpu"] = True  # rl_games starts the group, averages gradients, and adds the rank to the seed
    env_cfg.seed = params["seed"]


def _fitting_minibatch(size: int, horizon: int, num_envs: int, key: str = "minibatch_size") -> int:
    """rl_games' ``minibatch_size`` for a batch of ``horizon`` steps of ``num_envs`` envs.

    rl_games (and so Isaac Lab's train.py) refuses a size that does not divide the batch. A size above
    the batch is a config tuned for more envs than given (``--num_envs 64``): the batch becomes one
    mini-batch, said in one line. A smaller size that does not divide it is refused, naming the sizes
    that do near it.
    """
    batch = horizon * num_envs
    if size > batch:
        print(
            f"[simlab] agent.params.config.{key}={size} is more than a rollout of {horizon} steps x"
            f" {num_envs} envs holds: training with one mini-batch of {batch}.",
            flush=True,
        )
        return batch
    if batch % size:
        below = next(d for d in range(size, 0, -1) if batch % d == 0)
        above = next(d for d in range(size, batch + 1) if batch % d == 0)
        raise ConfigError(
            f"agent.params.config.{key}={size} does not divide the batch of {horizon} steps x {num_envs}"
            f" envs = {batch}, which rl_games requires; sizes that do: {below} or {above} (or change --num_envs)."
        )
    return size


def _clips(agent_cfg: dict) -> tuple[float, float]:
    env = agent_cfg["params"].get("env", {})
    return float(env.get("clip_observations", math.inf)), float(env.get("clip_actions", math.inf))


def _runner(env: gym.Env, agent_cfg: dict, observer: Any = None) -> tuple[Runner, RlGamesVecEnvWrapper]:
    clip_obs, clip_actions = _clips(agent_cfg)
    device = agent_cfg["params"]["config"]["device"]
    wrapped = RlGamesVecEnvWrapper(env, device, clip_obs, clip_actions)
    register_rl_games_env(wrapped)
    runner = Runner(observer or SimlabAlgoObserver())
    with contextlib.redirect_stdout(io.StringIO()):
        runner.load(copy.deepcopy(agent_cfg))
    return runner, wrapped


def train(
    env: gym.Env, agent_cfg: dict, run_dir: str | None, args: argparse.Namespace, resume_path: str | None
) -> None:
    """Train; ``run_dir`` None (ranks other than 0 of a distributed run) writes nothing that is kept."""
    if run_dir is None:
        # rl_games creates its folders on every rank (only rank 0 writes into them): give it a throwaway one
        with tempfile.TemporaryDirectory(prefix="simlab_rl_games_rank_") as scratch:
            return _train(env, agent_cfg, os.path.join(scratch, "run"), args, resume_path)
    return _train(env, agent_cfg, run_dir, args, resume_path)


def _train(env: gym.Env, agent_cfg: dict, run_dir: str, args: argparse.Namespace, resume_path: str | None) -> None:
    cfg = copy.deepcopy(agent_cfg)
    config = cfg["params"]["config"]
    config["train_dir"], config["full_experiment_name"] = os.path.split(run_dir)
    bar: dict[str, ProgressBar] = {}  # made at the first epoch
    world_size = int(os.environ.get("WORLD_SIZE", "1")) if config.get("multi_gpu") else 1
    steps_per_epoch = config["horizon_length"] * env.unwrapped.num_envs * world_size  # all ranks' steps

    def on_epoch(frame: int, epoch: int, total_time: float) -> None:
        if agent.global_rank != 0:
            return
        if "bar" not in bar:
            bar["bar"] = ProgressBar(total=config["max_epochs"], initial=epoch - 1, desc="rl_games")
        rewards = getattr(agent, "game_rewards", None)
        reward = float(rewards.get_mean()[0]) if rewards is not None and rewards.current_size > 0 else None
        # rl_games' total_time counts from train(), as the bar's own sum does
        bar["bar"].update(1, steps=steps_per_epoch, seconds=total_time - bar["bar"].seconds, reward=reward)

    runner, _ = _runner(env, cfg, SimlabAlgoObserver(on_epoch=on_epoch))
    agent = runner.algo_factory.create(runner.algo_name, base_name="run", params=runner.params)
    if config.get("multi_gpu"):  # the agent has started the process group
        distributed.check_same_settings(args.shared_settings)
    optimizers = [agent.optimizer]
    if getattr(agent, "has_central_value", False):
        optimizers.append(agent.central_value_net.optimizer)
    if resume_path:
        with weights_only_copy(resume_path, getattr(args, "trust_checkpoint", False)) as path:
            agent.restore(path)
        _use_configured_learning_rates(agent)
        print(f"[simlab] Resumed from {resume_path} at epoch {agent.epoch_num}")
    guard_optimizers(optimizers, "agent.params.config.learning_rate")
    verbose = bool(getattr(args, "verbose", False))
    try:
        with atomic_torch_saves(), contextlib.nullcontext() if verbose else contextlib.redirect_stdout(io.StringIO()):
            agent.train()
    except KeyboardInterrupt:
        if agent.global_rank == 0:
            path = os.path.join(agent.nn_dir, f"last_{config['name']}_ep_{agent.epoch_num}_interrupted")
            with atomic_torch_saves():
                agent.save(path)
            print(f"\n[simlab] Interrupted: saved {path}.pth")
        raise
    except TrainingDivergedError as e:
        path = os.path.join(agent.nn_dir, f"last_{config['name']}_ep_{agent.epoch_num}_diverged")
        with atomic_torch_saves():
            agent.save(path)
        raise TrainingDivergedError(f"{e} Saved the last good weights to {path}.pth.") from None
    finally:
        if "bar" in bar:
            bar["bar"].close()


class _RlGamesActor(nn.Module):
    """Observation clipping and normalization, the network's mean, and rl_games' action rescaling."""

    def __init__(self, model: nn.Module, clip_obs: float, clip_actions: float):
        super().__init__()
        self.model = copy.deepcopy(model)
        self.clip_obs, self.clip_actions = clip_obs, clip_actions

    def forward(self, obs: torch.Tensor) -> torch.Tensor:
        obs = torch.clamp(obs, -self.clip_obs, self.clip_obs)
        mu = self.model.a2c_network({"obs": self.model.norm_obs(obs)})[0]
        # the player clamps the mean to [-1, 1] and rescales it to the action space [-clip, clip]
        return torch.clamp(mu, -1.0, 1.0) * self.clip_actions


class _RlGamesRecurrentActor(_RlGamesActor):
    """The actor of a network with an RNN (rl_games' ``network.rnn``, e.g. an LSTM): each env's hidden
    state is carried from step to step and zeroed where ``restarted()`` says an episode has just begun,
    as rl_games' player zeroes it at the envs that are done."""

    def __init__(self, model: nn.Module, clip_obs: float, clip_actions: float, restarted: Any):
        super().__init__(model, clip_obs, clip_actions)
        self._restarted = restarted
        self.states: list[torch.Tensor] | None = None

    def forward(self, obs: torch.Tensor) -> torch.Tensor:
        if self.states is None:  # (layers, envs, units) per state tensor, as rl_games' player makes them
            defaults = self.model.get_default_rnn_state()
            self.states = [obs.new_zeros(s.shape[0], obs.shape[0], s.shape[2]) for s in defaults]
        fresh = self._restarted().to(obs.device).view(1, -1, 1)
        states = [torch.where(fresh, torch.zeros_like(s), s) for s in self.states]
        obs = torch.clamp(obs, -self.clip_obs, self.clip_obs)
        out = self.model.a2c_network({"obs": self.model.norm_obs(obs), "rnn_states": states, "seq_length": 1})
        self.states = list(out[-1])
        return torch.clamp(out[0], -1.0, 1.0) * self.clip_actions


def _use_configured_learning_rates(agent: Any) -> None:
    """rl_games' ``restore`` loads the optimizers with the learning rates they had when saved, and the
    configured one (``agent.params.config.learning_rate``, kept as ``last_lr``) only takes over after
    the first epoch: that epoch would silently train at the checkpoint's rate. It applies at once."""
    for group in agent.optimizer.param_groups:
        group["lr"] = float(agent.last_lr)
    if getattr(agent, "has_central_value", False):
        for group in agent.central_value_net.optimizer.param_groups:
            group["lr"] = float(agent.central_value_net.lr)


def _restore_on_device(player: Any, checkpoint: str, device: str, trust: bool = False) -> None:
    """rl_games' ``restore`` without ``map_location``: load a GPU-trained checkpoint on any device
    (weights only unless ``trust``)."""
    state = torch_load(checkpoint, map_location=device, trust=trust)
    model_state = {k.replace("_orig_mod.", ""): v for k, v in state["model"].items()}
    player.model.load_state_dict(model_state)
    if player.normalize_input and "running_mean_std" in state:
        player.model.running_mean_std.load_state_dict(state["running_mean_std"])


def load_policy(env: gym.Env, agent_cfg: dict, checkpoint: str, trust: bool = False) -> Policy:
    runner, wrapped = _runner(env, agent_cfg)
    runner.params["config"]["env_info"] = wrapped.get_env_info()
    runner.params["config"]["vec_env"] = wrapped
    with contextlib.redirect_stdout(io.StringIO()):
        player = runner.create_player()
    _restore_on_device(player, checkpoint, agent_cfg["params"]["config"]["device"], trust)
    player.model.eval()
    clip_obs, clip_actions = _clips(agent_cfg)
    if not math.isfinite(clip_actions):
        raise ValueError("rl_games play needs a finite params.env.clip_actions (the action space bounds).")
    if player.is_rnn:  # the hidden state restarts with each episode (a reset zeroes episode_length_buf)
        module = _RlGamesRecurrentActor(
            player.model, clip_obs, clip_actions, lambda: env.unwrapped.episode_length_buf == 0
        )
    else:
        module = _RlGamesActor(player.model, clip_obs, clip_actions)
    groups = wrapped.obs_groups["obs"]

    def inputs(obs: dict) -> dict[str, torch.Tensor]:
        return {"policy": wrapped.rl_games_input(obs)}  # as training saw them (an image's history stacked)

    shape = wrapped.observation_space.shape
    dim = shape if len(shape) == 3 else shape[0]  # an image input: its (H, W, C)
    not_exportable = (
        "exporting an rl_games policy with an RNN (its hidden state per env) is not supported yet"
        if player.is_rnn
        else None
    )
    device = agent_cfg["params"]["config"]["device"]
    return Policy(
        {"policy": module},
        inputs,
        {"policy": dim},
        device=device,
        not_exportable=not_exportable,
        obs_groups=list(groups),
    )
