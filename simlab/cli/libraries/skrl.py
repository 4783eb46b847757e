"""skrl adapter: skrl's ``Runner`` (PPO, AMP, IPPO, MAPPO) from the task's YAML, run folders, resume, Ctrl+C saves.

skrl trains on torch (default) or JAX (``--ml_framework jax`` or ``jax-numpy``); ``--distributed``
uses skrl's ``config.torch`` distributed mode in the process group simlab started.
"""

from __future__ import annotations

import argparse
import contextlib
import copy
import importlib
import logging
import math
import os
import re
import sys
from collections.abc import Iterator
from typing import Any

import gymnasium as gym
import torch
import torch.nn as nn

from simlab.cli.libraries.divergence import detached, non_finite
from simlab.cli.policy import Policy
from simlab.cli.session import check_mini_batches, check_training_settings
from simlab.rl.skrl import SkrlVecEnvWrapper
from simlab.rl.utils import require
from simlab.utils.errors import TrainingDivergedError
from simlab.utils.io import atomic_torch_saves
from simlab.utils.trust import weights_only_copy

ML_FRAMEWORKS = ("torch", "jax", "jax-numpy")


@contextlib.contextmanager
def _torchrun_hidden() -> Iterator[None]:
    """Hide torchrun's WORLD_SIZE while skrl is imported.

    skrl starts an NCCL process group when it is imported under torchrun, which fails on the CPU and
    clashes with the group simlab starts; :func:`_join_process_group` hands skrl simlab's group instead.
    """
    world_size = os.environ.pop("WORLD_SIZE", None)
    try:
        yield
    finally:
        if world_size is not None:
            os.environ["WORLD_SIZE"] = world_size


with _torchrun_hidden():
    require("skrl")
    from skrl import config as skrl_config  # noqa: E402


def _join_process_group() -> None:
    """Put skrl's ``config.torch`` in distributed mode on the process group simlab started.

    skrl reads its ranks once, at import, into these (read-only) attributes; its agents then
    broadcast the initial weights, average the gradients and let only rank 0 write.
    """
    import torch.distributed as dist

    torch_cfg = skrl_config.torch
    torch_cfg._rank = dist.get_rank()
    torch_cfg._world_size = dist.get_world_size()
    torch_cfg._local_rank = int(os.environ.get("LOCAL_RANK", "0"))
    torch_cfg._is_distributed = torch_cfg._world_size > 1


class _DropWarning(logging.Filter):
    """Drops the log records that contain ``text``."""

    def __init__(self, text: str):
        super().__init__()
        self.text = text

    def filter(self, record: logging.LogRecord) -> bool:
        return self.text not in record.getMessage()


def _runner_class(ml_framework: str) -> type:
    """skrl's ``Runner`` for ``ml_framework`` (torch, jax, or jax with numpy arrays)."""
    if ml_framework not in ML_FRAMEWORKS:
        raise ValueError(f"Unknown --ml_framework '{ml_framework}'. Allowed: {list(ML_FRAMEWORKS)}.")
    if ml_framework == "torch":
        return importlib.import_module("skrl.utils.runner.torch").Runner
    # JAX takes 75% of a GPU's memory at start-up by default, leaving too little to the simulation
    # and torch in the same process; allocate as needed instead (a user's own setting wins).
    os.environ.setdefault("XLA_PYTHON_CLIENT_PREALLOCATE", "false")
    require("jax")
    require("flax")
    require("optax")
    skrl_config.jax.backend = "jax" if ml_framework == "jax" else "numpy"
    return importlib.import_module("skrl.utils.runner.jax").Runner


def _wrap(env: gym.Env, ml_framework: str) -> Any:
    """The env in skrl's Isaac Lab wrapper for ``ml_framework``.

    skrl's JAX wrapper warns at import that "Isaac Lab runs on GPU" when JAX has no GPU; a simlab env
    on the CPU does not, so for CPU envs that warning is dropped (it stays where it is true). skrl is
    also told the env's device, so it does not warn about its default ``cuda:0`` on a CPU machine.
    """
    framework = "jax" if ml_framework.startswith("jax") else "torch"
    # skrl's default device is cuda:<local rank>; components built without a device take the env's
    device = str(env.unwrapped.device)
    if framework == "jax":
        skrl_config.jax.device = device
    else:
        skrl_config.torch.device = device
    if framework == "torch" or device.startswith("cuda"):
        return SkrlVecEnvWrapper(env, ml_framework=framework, wrapper="isaaclab")
    drop = _DropWarning("runs on GPU, but there is no GPU backend for JAX")
    skrl_logger = logging.getLogger("skrl")
    skrl_logger.addFilter(drop)
    try:
        return SkrlVecEnvWrapper(env, ml_framework=framework, wrapper="isaaclab")
    finally:
        skrl_logger.removeFilter(drop)


def _log_to_current_stderr() -> None:
    """Point skrl's log handler at today's ``sys.stderr``.

    skrl's handler keeps the stream that was ``sys.stderr`` when skrl was imported; a caller that
    swapped it since (a notebook's or a test's capture) may have closed that one, and every skrl log
    line then ends in a "--- Logging error ---" traceback."""
    for handler in logging.getLogger("skrl").handlers:
        if type(handler) is logging.StreamHandler:
            handler.stream = sys.stderr  # not setStream: it flushes the old stream, which may be closed


def experiment_name(agent_cfg: dict, task: str) -> str:
    return agent_cfg["agent"]["experiment"]["directory"]


def configure(agent_cfg: dict, args: argparse.Namespace, env_cfg: Any) -> None:
    if args.seed is not None:
        agent_cfg["seed"] = args.seed
    if getattr(args, "max_iterations", None) is not None:
        agent_cfg["trainer"]["timesteps"] = args.max_iterations * agent_cfg["agent"]["rollouts"]
    ml_framework = getattr(args, "ml_framework", None) or "torch"
    if ml_framework not in ML_FRAMEWORKS:
        raise ValueError(f"Unknown --ml_framework '{ml_framework}'. Allowed: {list(ML_FRAMEWORKS)}.")
    if ml_framework != "torch" and str(agent_cfg["agent"].get("class", "")).upper() == "AMP":
        raise ValueError(
            f"skrl's AMP agent exists for torch only; drop --ml_framework {ml_framework} (torch is the default)."
        )
    if getattr(args, "distributed", False):
        if ml_framework != "torch":
            raise ValueError("--distributed trains skrl on torch; drop --ml_framework or use --ml_framework torch.")
        _join_process_group()
    agent_cfg["trainer"]["close_environment_at_exit"] = False
    settings = agent_cfg["agent"]
    check_training_settings(
        args,
        {
            "agent.agent.rollouts": settings.get("rollouts"),
            "agent.agent.learning_epochs": settings.get("learning_epochs"),
            "agent.agent.mini_batches": settings.get("mini_batches"),
            "agent.trainer.timesteps": agent_cfg["trainer"]["timesteps"],
        },
        {"agent.agent.learning_rate": settings.get("learning_rate")},
    )
    num_envs, rollouts = env_cfg.scene.num_envs, settings.get("rollouts")
    rollout = f"{num_envs} envs x {rollouts} rollouts"
    check_mini_batches(args, "agent.agent.mini_batches", settings.get("mini_batches"), num_envs * rollouts, rollout)
    # skrl's "auto" intervals are timesteps/100 and /10, which is 0 (never) in short runs: keep them >= 1
    timesteps, rollouts = agent_cfg["trainer"]["timesteps"], agent_cfg["agent"]["rollouts"]
    exp = agent_cfg["agent"]["experiment"]
    if exp.get("write_interval", "auto") == "auto":
        exp["write_interval"] = max(1, timesteps // 100)
    if exp.get("checkpoint_interval", "auto") == "auto":
        exp["checkpoint_interval"] = max(rollouts, timesteps // 10 // rollouts * rollouts)
    env_cfg.seed = agent_cfg["seed"]


def make_runner(env: gym.Env, agent_cfg: dict, run_dir: str | None, ml_framework: str = "torch") -> Any:
    """skrl's Runner; ``run_dir`` None (playing, or ranks other than 0) writes nothing."""
    _log_to_current_stderr()
    cfg = copy.deepcopy(agent_cfg)
    exp = cfg["agent"]["experiment"]
    if run_dir is None:  # playing, or a rank other than 0: write nothing
        exp["write_interval"] = 0
        exp["checkpoint_interval"] = 0
        cfg["trainer"]["disable_progressbar"] = True
    else:
        exp["directory"], exp["experiment_name"] = os.path.split(run_dir)
    runner_class = _runner_class(ml_framework)
    # skrl's wrapper resets the env with the seed skrl holds when the wrapper is built (its PRNG key,
    # the seed plus the rank): seed skrl first. The Runner then seeds again with the same value.
    from skrl.utils import set_seed

    rank = skrl_config.torch.rank if skrl_config.torch.is_distributed else 0
    cfg["seed"] = set_seed(cfg.get("seed")) - rank
    return runner_class(_wrap(env, ml_framework), cfg)


def _continue_counting(agent: Any, start: int) -> None:
    """Make the agent see timesteps ``start + t``: skrl's trainer always counts from 0, so without this
    a resumed run would log from step 0 again and name its checkpoints as if it had just begun."""
    for name in ("pre_interaction", "act", "record_transition", "post_interaction"):
        method = getattr(agent, name)

        def shifted(*args: Any, timestep: int, timesteps: int, _method: Any = method, **kwargs: Any) -> Any:
            return _method(*args, timestep=timestep + start, timesteps=timesteps + start, **kwargs)

        setattr(agent, name, shifted)


def _use_configured_learning_rate(agent: Any, learning_rate: Any) -> None:
    """skrl's ``load`` restores the optimizer with the learning rate it had when saved, which would
    silently override ``agent.agent.learning_rate`` given for the resumed run. The configured rate
    applies instead (a KL-adaptive schedule restarts from it, as rsl_rl's adaptive schedule does)."""
    import torch

    optimizer = getattr(agent, "optimizer", None)
    if not isinstance(optimizer, torch.optim.Optimizer) or not isinstance(learning_rate, (int, float)):
        return  # JAX optimizers, multi-agent dicts: left as skrl restores them
    for group in optimizer.param_groups:
        group["lr"] = float(learning_rate)


def _timestep_of(checkpoint: str) -> int:
    """The timestep in an ``agent_<timestep>.pt`` checkpoint name (0 for other names)."""
    match = re.match(r"agent_(\d+)\.pt$", os.path.basename(checkpoint))
    return int(match.group(1)) if match else 0


def _stateful_modules(modules: dict, prefix: str = "") -> dict[str, Any]:
    """skrl's checkpoint modules (nested per agent for IPPO / MAPPO) that have a state dict, by dotted name."""
    found = {}
    for name, module in modules.items():
        if isinstance(module, dict):
            found.update(_stateful_modules(module, f"{prefix}{name}."))
        elif hasattr(module, "state_dict"):
            found[f"{prefix}{name}"] = module
    return found


def _guard_updates(agent: Any) -> None:
    """Stop at the first update whose losses or weights are not finite, with the weights from before it.

    A too-high learning rate shows in skrl as an infinite value loss (its gradient clipping keeps
    the weights finite, but useless); the agent then keeps "training" on garbage.
    """
    modules = _stateful_modules(agent.checkpoint_modules)
    update = agent.update

    def checked_update(*, timestep: int, timesteps: int, **kwargs: Any) -> None:  # IPPO / MAPPO add uid=
        good = {name: detached(m.state_dict()) for name, m in modules.items()}
        update(timestep=timestep, timesteps=timesteps, **kwargs)
        bad = [
            f"'{tag}' is {values[-1]}"
            for tag, values in agent.tracking_data.items()
            if tag.startswith("Loss") and values and not math.isfinite(values[-1])
        ]
        weights = [p for m in modules.values() if isinstance(m, nn.Module) for p in m.parameters()]
        if not bad and not non_finite(weights):
            return
        for name, module in modules.items():
            module.load_state_dict(good[name])
        what = ", ".join(bad) or "the weights are not finite"
        raise TrainingDivergedError(
            f"Training diverged at timestep {timestep + 1}: {what}. "
            "Lower the learning rate (agent.agent.learning_rate) or check the rewards and observations for huge values."
        )

    agent.update = checked_update


STYLE_REWARD_TAG = "Reward / Style reward (mean)"


def _track_style_reward(agent: Any) -> None:
    """Log the discriminator's reward of each rollout as ``STYLE_REWARD_TAG`` (skrl's AMP logs only losses).

    It is skrl's style reward, ``-log(max(1 - sigmoid(D(amp_obs)), 1e-4))``, before
    ``style_reward_scale``, judged by the discriminator of that rollout (before its update): it
    rises as the policy's motion becomes harder to tell from the reference clip's.
    """
    update = agent.update

    def update_and_track(*, timestep: int, timesteps: int, **kwargs: Any) -> None:
        amp_obs = agent.memory.get_tensor_by_name("amp_observations")
        with torch.no_grad():
            logits, _ = agent.discriminator.act(
                {"observations": agent._amp_observation_preprocessor(amp_obs)}, role="discriminator"
            )
            reward = -torch.log(torch.clamp(1.0 - torch.sigmoid(logits), min=1e-4))
        agent.track_data(STYLE_REWARD_TAG, reward.mean().item())
        update(timestep=timestep, timesteps=timesteps, **kwargs)

    agent.update = update_and_track


def train(
    env: gym.Env, agent_cfg: dict, run_dir: str | None, args: argparse.Namespace, resume_path: str | None
) -> None:
    """Train; ``run_dir`` None (ranks other than 0 of a distributed run) writes nothing."""
    ml_framework = getattr(args, "ml_framework", None) or "torch"
    runner = make_runner(env, agent_cfg, run_dir, ml_framework)
    start = 0
    if resume_path:
        kind = "torch" if ml_framework == "torch" else "pickle"  # skrl on JAX pickles its checkpoints
        with weights_only_copy(resume_path, getattr(args, "trust_checkpoint", False), kind) as path:
            runner.agent.load(path)
        _use_configured_learning_rate(runner.agent, agent_cfg["agent"].get("learning_rate"))
        start = _timestep_of(resume_path)
        _continue_counting(runner.agent, start)
        print(f"[simlab] Resumed weights, optimizer and normalizers from {resume_path} at timestep {start}")
    agent = runner.agent
    if ml_framework == "torch":  # the guard reads torch modules' state
        _guard_updates(agent)
        if getattr(agent, "discriminator", None) is not None:
            _track_style_reward(agent)
    checkpoints = os.path.join(run_dir, "checkpoints") if run_dir is not None else None
    steps = env.unwrapped.common_step_counter

    def save_now() -> str:
        path = os.path.join(checkpoints, f"agent_{start + env.unwrapped.common_step_counter - steps}.pt")
        os.makedirs(checkpoints, exist_ok=True)
        with atomic_torch_saves():
            agent.save(path)
        return path

    try:
        with atomic_torch_saves():
            runner.run("train")
    except KeyboardInterrupt:
        if checkpoints is not None:
            print(f"\n[simlab] Interrupted: saved {save_now()}")
        if getattr(agent, "writer", None) is not None:  # the TensorBoard points still queued
            agent.writer.flush()
        raise
    except TrainingDivergedError as e:
        if checkpoints is None:
            raise
        raise TrainingDivergedError(f"{e} Saved the last good weights to {save_now()}.") from None
    if checkpoints is None:
        return
    final = os.path.join(checkpoints, f"agent_{start + agent_cfg['trainer']['timesteps']}.pt")
    if not os.path.isfile(final):
        os.makedirs(checkpoints, exist_ok=True)
        with atomic_torch_saves():
            runner.agent.save(final)


class _SkrlActor(nn.Module):
    """Observation preprocessor + the policy model's mean action; for a Discrete or MultiDiscrete
    action space (categorical policies, whose output is logits) the most likely choice of each part."""

    def __init__(self, model: nn.Module, preprocessor: Any, action_space: gym.spaces.Space | None = None):
        super().__init__()
        self.model = copy.deepcopy(model)
        self.preprocessor = copy.deepcopy(preprocessor) if isinstance(preprocessor, nn.Module) else nn.Identity()
        self.choices: list[int] | None = None  # the number of choices of each discrete part
        if isinstance(action_space, gym.spaces.Discrete):
            self.choices = [int(action_space.n)]
        elif isinstance(action_space, gym.spaces.MultiDiscrete):
            self.choices = [int(n) for n in action_space.nvec]

    def forward(self, obs: torch.Tensor) -> torch.Tensor:
        mean, _ = self.model.compute({"observations": self.preprocessor(obs)}, role="policy")
        if self.choices is None:
            return mean
        return torch.stack([logits.argmax(dim=-1) for logits in mean.split(self.choices, dim=-1)], dim=-1)


def load_policy(env: gym.Env, agent_cfg: dict, checkpoint: str, trust: bool = False) -> Policy:
    agent_cfg = copy.deepcopy(agent_cfg)
    for memory in ("motion_dataset", "reply_buffer"):  # AMP's training memories: playing fills none
        if memory in agent_cfg:
            agent_cfg[memory]["memory_size"] = agent_cfg["agent"].get("amp_batch_size", 512)
    runner = make_runner(env, agent_cfg, None)  # torch models: play and export run on torch
    agent = runner.agent
    with weights_only_copy(checkpoint, trust) as path:
        agent.load(path)
    agent.enable_training_mode(False)
    device = str(agent.device)
    if hasattr(agent, "policies"):  # IPPO / MAPPO: one actor per agent, fed its own observation
        names = list(agent.possible_agents)
        modules = {a: _SkrlActor(agent.policies[a], agent._observation_preprocessor[a]) for a in names}
        dims = {a: gym.spaces.flatdim(env.unwrapped.observation_spaces[a]) for a in names}

        def inputs(obs: dict) -> dict[str, torch.Tensor]:
            return {a: obs[a].reshape(obs[a].shape[0], -1) for a in names}

        return Policy(modules, inputs, dims, device=device)
    from skrl.utils.spaces.torch import compute_space_size, flatten_tensorized_space, tensorize_space

    module = _SkrlActor(agent.policy, agent._observation_preprocessor, env.unwrapped.single_action_space)
    space = env.unwrapped.single_observation_space["policy"]
    dim = compute_space_size(space, occupied_size=True)  # as skrl's wrapper flattens (a Discrete: 1)

    def inputs(obs: dict) -> dict[str, torch.Tensor]:  # Dict and Tuple observations flattened as skrl does
        return {"policy": flatten_tensorized_space(tensorize_space(space, obs["policy"]))}

    return Policy({"policy": module}, inputs, {"policy": dim}, device=device)
