"""rsl_rl adapter: ``OnPolicyRunner`` training with a progress bar, resume and Ctrl+C saves; ``DistillationRunner``
(an agent config with ``class_name="DistillationRunner"``) distils a teacher checkpoint into a student."""

from __future__ import annotations

import argparse
import contextlib
import io
import math
import os
import statistics
from collections.abc import Callable
from typing import Any

import gymnasium as gym
import torch

from simlab.cli.libraries.divergence import detached, non_finite
from simlab.cli.libraries.progress import ProgressBar
from simlab.cli.policy import ClampActions, Policy
from simlab.cli.session import check_mini_batches, check_training_settings
from simlab.rl.utils import require
from simlab.utils.errors import CheckpointError, ConfigError, TrainingDivergedError
from simlab.utils.io import atomic_torch_saves
from simlab.utils.startup import mark
from simlab.utils.trust import torch_load, weights_only_copy
from simlab.utils.versions import warn_once

require("rsl_rl")
from rsl_rl.runners import DistillationRunner, OnPolicyRunner  # noqa: E402
from rsl_rl.utils.logger import Logger  # noqa: E402

from simlab.rl.rsl_rl import RslRlOnPolicyRunnerCfg, RslRlVecEnvWrapper  # noqa: E402
from simlab.rl.rsl_rl.fast_update import FastPPOUpdate, fast_update_unsupported  # noqa: E402
from simlab.rl.rsl_rl.graphed_act import GraphedAct, graphed_act_unsupported  # noqa: E402
from simlab.rl.rsl_rl.vecenv_wrapper import stack_image_history  # noqa: E402

READS_FINAL_OBS = False
"""rsl_rl bootstraps a time-out from its value estimate, never from ``extras["final_obs"]``: its
training env need not compute every observation (a height scan's rays too) a second time per step."""


def experiment_name(agent_cfg: RslRlOnPolicyRunnerCfg, task: str) -> str:
    return agent_cfg.experiment_name


def is_distillation(agent_cfg: Any) -> bool:
    """True for a distillation agent (Isaac Lab's train.py picks the runner by ``class_name`` too)."""
    return getattr(agent_cfg, "class_name", None) == "DistillationRunner"


def needs_teacher(agent_cfg: Any) -> bool:
    """A distillation trains nothing without the teacher's checkpoint (``--checkpoint``)."""
    return is_distillation(agent_cfg)


def is_teacher_checkpoint(path: str, trust: bool = False) -> bool:
    """True for a checkpoint that holds a policy to distil (a PPO run's ``actor_state_dict``, no student):
    it may come from another task (the state cartpole teaches the camera one), so the checks that a
    checkpoint fits this task are the teacher's layer sizes when it loads."""
    return _holds_teacher(torch_load(path, map_location="cpu", trust=trust))


def _holds_teacher(saved: Any) -> bool:
    """A loaded checkpoint with a PPO run's actor and no student."""
    return isinstance(saved, dict) and "actor_state_dict" in saved and "student_state_dict" not in saved


def configure(agent_cfg: RslRlOnPolicyRunnerCfg, args: argparse.Namespace, env_cfg: Any) -> None:
    if args.seed is not None:
        agent_cfg.seed = args.seed
    agent_cfg.device = env_cfg.sim.device
    if getattr(args, "max_iterations", None) is not None:
        agent_cfg.max_iterations = args.max_iterations
    if getattr(args, "run_name", None):
        agent_cfg.run_name = args.run_name
    algorithm = agent_cfg.algorithm
    check_training_settings(
        args,
        {
            "agent.num_steps_per_env": agent_cfg.num_steps_per_env,
            "agent.algorithm.num_learning_epochs": getattr(algorithm, "num_learning_epochs", None),
            "agent.algorithm.num_mini_batches": getattr(algorithm, "num_mini_batches", None),
            "agent.algorithm.gradient_length": getattr(algorithm, "gradient_length", None),
            "agent.save_interval": agent_cfg.save_interval,
            "agent.max_iterations": agent_cfg.max_iterations,
        },
        {"agent.algorithm.learning_rate": getattr(algorithm, "learning_rate", None)},
    )
    num_envs, steps = env_cfg.scene.num_envs, agent_cfg.num_steps_per_env
    if _recurrent(agent_cfg):  # rsl_rl splits a recurrent model's rollout by env, keeping each env's sequence
        samples, rollout = num_envs, f"{num_envs} envs, split by env for a recurrent model"
    else:
        samples, rollout = num_envs * steps, f"{num_envs} envs x {steps} steps"
    mini_batches = getattr(algorithm, "num_mini_batches", None)
    check_mini_batches(args, "agent.algorithm.num_mini_batches", mini_batches, samples, rollout)
    env_cfg.seed = agent_cfg.seed


def _recurrent(agent_cfg: RslRlOnPolicyRunnerCfg) -> bool:
    models = [getattr(agent_cfg, name, None) for name in ("actor", "critic", "student", "teacher")]
    return any("RNN" in str(getattr(model, "class_name", "")) for model in models)


class _ProgressLogger(Logger):
    """rsl_rl's logger (TensorBoard, git state), with a progress bar instead of a block per iteration."""

    verbose = False

    def __init__(self, *args: Any, **kwargs: Any):
        super().__init__(*args, **kwargs)
        self._finished: list[tuple[torch.Tensor, torch.Tensor, torch.Tensor]] = []
        # (refreshed flag, logs) of each step of an env with log_refresh_on_device, and the logs
        # that count until the next refresh (what extras["log"] would hold in Isaac Lab's way)
        self._env_logs: list[tuple[torch.Tensor, dict]] = []
        self.current_env_log: dict | None = None
        self.rollout_seconds = 0.0  # rsl_rl's collect_time, summed over the iterations
        self.update_seconds = 0.0  # rsl_rl's learn_time, summed

    def log(self, it: int, start_it: int, total_it: int, collect_time: float, learn_time: float, **kw: Any) -> None:
        mark("first iteration")
        self.rollout_seconds += collect_time
        self.update_seconds += learn_time
        self._flush_finished()
        if self.writer is None:  # a rank other than 0 of a distributed run: rank 0 reports
            return
        if not hasattr(self, "_bar"):
            self._bar = ProgressBar(total=total_it, initial=start_it, desc="rsl_rl")
        sink = contextlib.nullcontext() if self.verbose else contextlib.redirect_stdout(io.StringIO())
        with sink:
            super().log(
                it=it, start_it=start_it, total_it=total_it, collect_time=collect_time, learn_time=learn_time, **kw
            )
        reward = statistics.mean(self.rewbuffer) if self.rewbuffer else None
        length = statistics.mean(self.lenbuffer) if self.lenbuffer else None
        steps = self.cfg["num_steps_per_env"] * self.num_envs * self.gpu_world_size  # all ranks' steps
        self._bar.update(1, steps=steps, seconds=collect_time + learn_time, reward=reward, ep_len=length)

    def process_env_step(self, rewards, dones, extras, intrinsic_rewards=None) -> None:
        """rsl_rl's bookkeeping without its per-step device-to-host copies.

        rsl_rl copies the returns of finished episodes to the host every step, which makes the
        CPU wait for the GPU each step. Here they stay on the device until ``log``, once per
        iteration; the buffers then hold the same episodes in the same order. So do the env's
        episode logs where the env leaves choosing the fresh ones to us (``log_refresh_on_device``).
        """
        if self.writer is None or intrinsic_rewards is not None:
            return super().process_env_step(rewards, dones, extras, intrinsic_rewards)
        if "episode" in extras:
            self.ep_extras.append(extras["episode"])
        elif "log_refreshed" in extras:
            self._env_logs.append((extras["log_refreshed"], extras["log"]))
        elif "log" in extras:
            self.ep_extras.append(extras["log"])
        self._add_episode_step(rewards, dones)

    def _add_episode_step(self, rewards: torch.Tensor, dones: torch.Tensor) -> None:
        """Add a step's rewards to the running episode sums and restart the episodes that ended."""
        self.cur_reward_sum += rewards
        self.cur_episode_length += 1
        done = dones > 0
        self._finished.append((done, self.cur_reward_sum.clone(), self.cur_episode_length.clone()))
        self.cur_reward_sum.masked_fill_(done, 0.0)
        self.cur_episode_length.masked_fill_(done, 0.0)

    def _flush_finished(self) -> None:
        if self._env_logs:
            refreshed = torch.stack([flag for flag, _ in self._env_logs]).tolist()
            for fresh, (_, log) in zip(refreshed, self._env_logs):
                if fresh:
                    self.current_env_log = log
                if self.current_env_log is not None:  # the same dict object per step, as extras["log"] was
                    self.ep_extras.append(self.current_env_log)
            self._env_logs.clear()
        if not self._finished:
            return
        done, returns, lengths = (torch.stack(column) for column in zip(*self._finished))
        self._finished.clear()
        self.rewbuffer.extend(returns[done].tolist())  # step-major: the order rsl_rl keeps
        self.lenbuffer.extend(lengths[done].tolist())

    def close_bar(self) -> None:
        """End the progress bar's line (so an error printed next starts on its own line)."""
        if hasattr(self, "_bar"):
            self._bar.close()

    def stop_logging_writer(self) -> None:
        self.close_bar()
        if self.writer is not None and hasattr(self.writer, "flush"):
            self.writer.flush()
        super().stop_logging_writer()


class _Runner(OnPolicyRunner):
    """rsl_rl's runner, joining the process group simlab started for ``--distributed``.

    rsl_rl would start an NCCL group itself, which the CPU lacks; in a group simlab started (NCCL on
    GPUs, gloo on the CPU) it gets the same ``multi_gpu`` settings and averages gradients as usual.
    """

    def _configure_multi_gpu(self) -> None:
        import torch.distributed as dist

        if not (dist.is_available() and dist.is_initialized()):
            return super()._configure_multi_gpu()
        self.gpu_world_size = dist.get_world_size()
        self.gpu_global_rank = dist.get_rank()
        self.gpu_local_rank = int(os.environ.get("LOCAL_RANK", "0"))
        self.is_distributed = self.gpu_world_size > 1
        self.cfg["multi_gpu"] = (
            {"global_rank": self.gpu_global_rank, "local_rank": self.gpu_local_rank, "world_size": self.gpu_world_size}
            if self.is_distributed
            else None
        )


class _DistillationRunner(_Runner, DistillationRunner):
    """rsl_rl's distillation runner (it refuses to learn before a teacher is loaded), in simlab's process group."""


def make_runner(env: gym.Env, agent_cfg: RslRlOnPolicyRunnerCfg, log_dir: str | None) -> OnPolicyRunner:
    wrapped = RslRlVecEnvWrapper(env, clip_actions=agent_cfg.clip_actions)
    groups = list(wrapped.get_observations().keys())
    cfg = agent_cfg.to_rsl_rl_dict(groups)
    # rsl_rl's NaN check reads three flags back per step (each a CPU-GPU sync); simlab's env step
    # checks observations and rewards itself (simlab.envs.utils.cuda_graph).
    cfg["check_for_nan"] = False
    distill = is_distillation(agent_cfg)
    if distill:
        _check_distillation_groups(cfg["obs_groups"], groups, env.unwrapped)
    with contextlib.redirect_stdout(io.StringIO()):  # it prints the models; params/agent.yaml has them
        runner_class = _DistillationRunner if distill else _Runner
        runner = runner_class(wrapped, cfg, log_dir=log_dir, device=agent_cfg.device)
    if distill:  # simlab's fast update and graphed act are PPO's
        runner.update_kind, runner.act_kind = "rsl_rl's distillation", "eager"
        return runner
    runner.update_kind = use_fast_update(runner.alg, agent_cfg.fast_update)
    runner.act_kind = use_graphed_act(runner.alg, agent_cfg.graph_act)
    return runner


def _check_distillation_groups(obs_groups: dict[str, list[str]], groups: list[str], env: Any) -> None:
    """One line for a student or teacher set that names an observation group the env lacks (rsl_rl
    would fall back to the student's "policy" group for a missing teacher without a word)."""
    task = getattr(getattr(env, "spec", None), "id", None) or type(env).__name__
    for name in ("student", "teacher"):
        missing = [g for g in obs_groups[name] if g not in groups]
        if missing:
            raise ConfigError(
                f"The distillation's {name} reads the observation group '{missing[0]}', which {task} does not"
                f" have (its groups: {', '.join(groups)}). Add that group to the env's observations, or set"
                f" agent.obs_groups.{name}=[<groups>] (the {name}'s observations)."
            )


def use_graphed_act(alg: Any, setting: bool | None) -> str:
    """Replay rsl_rl's ``alg.act`` as a CUDA graph where ``setting`` (agent.graph_act) asks; says which runs."""
    if setting is False:
        return "eager"
    reason = graphed_act_unsupported(alg)
    if reason is not None:
        if setting:
            raise ValueError(f"agent.graph_act=true, but {reason}. Set agent.graph_act=null or false.")
        return f"eager ({reason})"
    alg.act = GraphedAct(alg)
    return "CUDA graph"


def use_fast_update(alg: Any, setting: bool | None) -> str:
    """Give ``alg`` simlab's fast PPO update where ``setting`` (agent.fast_update) asks; says which runs."""
    if setting is False:
        return "rsl_rl"
    if setting is None and torch.device(alg.device).type != "cuda":
        # on the CPU it is as fast as rsl_rl's (measured in docs/performance.md): keep the library's own
        return "rsl_rl (the fast update pays on CUDA; agent.fast_update=true runs it on the CPU too)"
    reason = fast_update_unsupported(alg)
    if reason is not None:
        if reason.startswith(("rsl-rl-lib ", "torch ")):  # another release than the one checked: never run it
            warn_once(f"{reason}; training uses rsl_rl's own update.")
        elif setting:
            raise ValueError(
                f"agent.fast_update=true, but simlab's fast PPO update does not cover {reason}. "
                "Set agent.fast_update=null (use it where it applies) or false (rsl_rl's own update)."
            )
        return f"rsl_rl ({reason})"
    alg.update = FastPPOUpdate(alg)
    return "fast (CUDA graph)" if alg.update.cuda_graph else "fast"


def install_progress_logger(runner: OnPolicyRunner, log_dir: str | None) -> _ProgressLogger:
    """Give ``runner`` simlab train's logger (a progress bar; finished episodes kept on the device),
    writing to ``log_dir`` (None: nothing); returns it."""
    runner.logger = _ProgressLogger(
        log_dir=log_dir,
        cfg=runner.cfg,
        env_cfg=runner.env.cfg,
        num_envs=runner.env.num_envs,
        is_distributed=runner.is_distributed,
        gpu_world_size=runner.gpu_world_size,
        gpu_global_rank=runner.gpu_global_rank,
        device=runner.device,
    )
    return runner.logger


def train(
    env: gym.Env,
    agent_cfg: RslRlOnPolicyRunnerCfg,
    run_dir: str | None,
    args: argparse.Namespace,
    resume_path: str | None,
) -> None:
    """Train; ``run_dir`` None (ranks other than 0 of a distributed run) writes nothing."""
    runner = make_runner(env, agent_cfg, run_dir)
    mark("runner")
    _mark_first_step(runner.env)
    logger = install_progress_logger(runner, run_dir)
    logger.verbose = bool(getattr(args, "verbose", False))
    _logs_without_host_sync(runner, logger)
    if run_dir is not None:
        update_name = "Student" if is_distillation(agent_cfg) else "PPO"
        print(
            f"[simlab] {update_name} update: {runner.update_kind}; policy in the rollout: {runner.act_kind}",
            flush=True,
        )
    import simlab

    runner.add_git_repo_to_log(simlab.__file__)
    trust = getattr(args, "trust_checkpoint", False)
    teacher = resume_path is not None and is_distillation(agent_cfg) and is_teacher_checkpoint(resume_path, trust)
    if teacher:
        _load_teacher(runner, resume_path, agent_cfg.device, trust)
        print(f"[simlab] Distilling the teacher {resume_path} into the student")
        resume_path = None  # the student starts fresh (random initial episode lengths as in a new run)
    elif resume_path:
        with weights_only_copy(resume_path, trust) as path:
            runner.load(path, map_location=agent_cfg.device)
        print(f"[simlab] Resumed from {resume_path} at iteration {runner.current_learning_iteration}")
    if getattr(args, "init_weights", None):
        init_weights(runner, args.init_weights, agent_cfg.device, trust)
        warm_up_critic(runner, getattr(args, "warmup_critic", 0))
    guard_divergence(runner, run_dir)
    on_checkpoint = getattr(args, "on_checkpoint", None)
    if on_checkpoint is not None:
        call_after_saves(runner, on_checkpoint)
    try:
        with atomic_torch_saves():
            # random initial episode lengths spread out the first resets of a fresh run; on resume they
            # would cut the first episodes short and log an untrained-looking return
            runner.learn(num_learning_iterations=agent_cfg.max_iterations, init_at_random_ep_len=not resume_path)
    except _StopTraining:
        logger.stop_logging_writer()
    except KeyboardInterrupt:
        if run_dir is not None:
            path = os.path.join(run_dir, f"model_{runner.current_learning_iteration}.pt")
            try:
                with atomic_torch_saves():
                    runner.save(path)
            except _StopTraining:  # the hook judged this last checkpoint and it met the goal
                logger.stop_logging_writer()
                print(f"\n[simlab] Interrupted: saved {path}, which met the goal: training ends there")
                return
            logger.stop_logging_writer()
            print(f"\n[simlab] Interrupted: saved {path}")
        raise
    except TrainingDivergedError:
        logger.stop_logging_writer()
        raise
    except OSError:  # the run folder cannot be written (full disk, read-only): nothing more to flush there
        logger.close_bar()
        raise


def init_weights(runner: OnPolicyRunner, checkpoint: str, device: str, trust: bool = False) -> None:
    """``--init_weights``: the actor (and the critic, where the file has one) start from ``checkpoint``'s
    weights; the optimizer, learning rate and iteration count start fresh. A layer of another size
    raises torch's error, which ``checkpoint_load_errors`` turns into one line."""
    with weights_only_copy(checkpoint, trust) as path:
        critic = "critic_state_dict" in torch_load(path, map_location="cpu", trust=trust)
        runner.load(path, load_cfg={"actor": True, "critic": critic}, map_location=device)
    models = "actor and critic" if critic else "actor (the critic starts untrained)"
    print(f"[simlab] Initialized the {models} from {checkpoint}; training starts at iteration 0")


def warm_up_critic(runner: OnPolicyRunner, iterations: int) -> None:
    """The run's first ``iterations`` updates train the critic only: after each, the actor's weights are put
    back and its optimizer moments cleared. (Within an update the actor still moves, so the adaptive
    learning rate sees the KL it would.) For an actor taken from a policy whose critic was not."""
    if iterations <= 0:
        return
    alg = runner.alg
    actor = alg._raw_actor
    kept = {name: value.detach().clone() for name, value in actor.state_dict().items()}
    update = alg.update  # rsl_rl's, or simlab's fast update
    left = [iterations]

    def update_critic_only(*args: Any, **kwargs: Any) -> Any:
        losses = update(*args, **kwargs)
        with torch.no_grad():
            for name, value in actor.state_dict().items():
                value.copy_(kept[name])  # in place: a captured graph keeps reading the same tensors
            for param in actor.parameters():
                for moment in alg.optimizer.state.get(param, {}).values():
                    if torch.is_tensor(moment):
                        moment.zero_()  # Adam's step too: its first actor step is a first step
        left[0] -= 1
        if left[0] == 0:
            alg.update = update
        return losses

    alg.update = update_critic_only
    print(f"[simlab] The first {iterations} iterations train the critic only")


def _load_teacher(runner: DistillationRunner, checkpoint: str, device: str, trust: bool) -> None:
    """Load a PPO checkpoint's actor as the teacher (rsl_rl's choice for a checkpoint with an actor);
    a teacher model of another shape is one line naming the first layer that differs."""
    with weights_only_copy(checkpoint, trust) as path:
        try:
            runner.load(path, load_cfg={"teacher": True}, map_location=device)
        except RuntimeError as e:
            first = next((line.strip() for line in str(e).splitlines()[1:] if line.strip()), str(e))
            raise CheckpointError(
                f"The teacher checkpoint '{checkpoint}' does not fit agent.teacher ({first}): the teacher's model"
                " and observation group must be those the checkpoint's policy was trained with. Nothing was trained."
            ) from e


def _logs_without_host_sync(runner: OnPolicyRunner, logger: _ProgressLogger) -> None:
    """Let the logger pick the env's fresh episode logs once per iteration (no host read per step).

    Not with RND: then rsl_rl's own bookkeeping reads ``extras["log"]`` each step."""
    env = runner.env.unwrapped
    if not hasattr(env, "log_refresh_on_device") or runner.cfg["algorithm"].get("rnd_cfg"):
        return
    env.log_refresh_on_device = True
    logger.current_env_log = env.extras.get("log")  # what the first steps log until a refresh


def _mark_first_step(wrapped: RslRlVecEnvWrapper) -> None:
    """Mark the start-up milestone "first env step" when the first step returns (then step as before)."""

    def first_step(actions: torch.Tensor):
        del wrapped.step  # later steps call the class's method directly
        out = wrapped.step(actions)
        mark("first env step")
        return out

    wrapped.step = first_step


class _StopTraining(Exception):
    """Raised after a checkpoint save whose ``on_checkpoint`` hook asked training to stop."""


def call_after_saves(runner: OnPolicyRunner, on_checkpoint: Callable[[str, int, dict[str, float]], bool]) -> None:
    """Call ``on_checkpoint(path, iteration, seconds)`` after each checkpoint the runner saves;
    ``seconds`` holds the rollout and update time so far. The hook returning True ends training there
    (``simlab bench solve`` stops at the first checkpoint that solves the task)."""
    save = runner.save

    def save_then_call(path: str, infos: dict | None = None) -> None:
        save(path, infos)
        seconds = {"rollout": runner.logger.rollout_seconds, "update": runner.logger.update_seconds}
        if on_checkpoint(path, runner.current_learning_iteration, seconds):
            raise _StopTraining

    runner.save = save_then_call


def guard_divergence(runner: OnPolicyRunner, run_dir: str) -> None:
    """Stop training when an update makes the losses or weights non-finite; save the last good weights.

    Before each update the learner's state is kept; if the update yields a NaN / infinite loss or
    weights, that state is saved as ``model_<iteration>.pt`` and :class:`TrainingDivergedError`
    says what happened, instead of rsl_rl failing later on a NaN action distribution.
    """
    update = runner.alg.update

    def checked_update() -> dict[str, float]:
        iteration = runner.current_learning_iteration
        good = detached(runner.alg.save())
        losses = update()
        bad_losses = [f"the {k} loss is {v}" for k, v in losses.items() if not math.isfinite(v)]
        state = runner.alg.save()
        models = [k.removesuffix("_state_dict") for k in state if k.endswith("_state_dict") and "optimizer" not in k]
        bad_weights = [m for m in models if non_finite(state[f"{m}_state_dict"].values())]
        if not bad_losses and not bad_weights:
            return losses
        path = os.path.join(run_dir, f"model_{iteration}.pt")
        with atomic_torch_saves():
            torch.save({**good, "iter": iteration, "infos": None}, path)
        what = ", ".join(bad_losses + [f"non-finite {w} weights" for w in bad_weights])
        raise TrainingDivergedError(
            f"Training diverged in iteration {iteration + 1}: {what}. Saved the last good weights to {path}. "
            f"Lower the learning rate (agent.algorithm.learning_rate, now {runner.alg.learning_rate:g}) "
            "or check the rewards and observations for huge values."
        )

    runner.alg.update = checked_update


def load_policy(env: gym.Env, agent_cfg: RslRlOnPolicyRunnerCfg, checkpoint: str, trust: bool = False) -> Policy:
    runner = make_runner(env, agent_cfg, None)
    played = "student" if is_distillation(agent_cfg) else "actor"  # what the checkpoint's policy is called
    saved = torch_load(checkpoint, map_location="cpu", trust=trust)  # read once for both checks
    if played == "student" and _holds_teacher(saved):
        raise CheckpointError(
            f"Checkpoint '{checkpoint}' holds a PPO policy (a teacher), not a distilled student: play it without"
            " --agent (the task's PPO agent), or distil it first (simlab train --agent <distillation entry point>"
            " --checkpoint <it>)."
        )
    if played == "actor" and "student_state_dict" in saved:
        raise CheckpointError(
            f"Checkpoint '{checkpoint}' holds a distilled student, not a PPO policy: play it with the distillation"
            " agent it was trained with (--agent rsl_rl_distillation_cfg_entry_point, or the task's other one)."
        )
    with weights_only_copy(checkpoint, trust) as path:
        runner.load(path, load_cfg={played: True}, map_location=agent_cfg.device)
    actor = runner.alg.get_policy()
    groups = runner.cfg["obs_groups"][played]
    if getattr(actor, "obs_groups_2d", None):  # a CNN actor: it reads one image group
        module, obs_shape = _image_actor(actor, groups)
    else:
        module, obs_shape = actor.as_jit(), actor.obs_dim
    if agent_cfg.clip_actions is not None:
        module = ClampActions(module, -agent_cfg.clip_actions, agent_cfg.clip_actions)

    def inputs(obs: dict) -> dict[str, torch.Tensor]:
        if len(groups) == 1 and obs[groups[0]].ndim in (4, 5):
            # (N, H, W, C) as the env gives it; an image history as one image of k * C channels
            return {"policy": stack_image_history(obs[groups[0]])}
        return {"policy": torch.cat([obs[g].reshape(obs[g].shape[0], -1) for g in groups], dim=-1)}

    return Policy({"policy": module}, inputs, {"policy": obs_shape}, device=agent_cfg.device, obs_groups=list(groups))


class _ImageActor(torch.nn.Module):
    """An rsl_rl CNN actor as an ``images -> actions`` module: (N, H, W, C) images, as the env gives them."""

    def __init__(self, model: torch.nn.Module):
        super().__init__()
        self.model = model  # rsl_rl's export form: forward(obs_1d, *obs_2d) with (N, C, H, W) images

    def forward(self, images: torch.Tensor) -> torch.Tensor:
        return self.model(images.new_zeros(images.shape[0], 0), images.permute(0, 3, 1, 2))


def _image_actor(actor, groups: list[str]) -> tuple[torch.nn.Module, tuple[int, ...]]:
    if len(groups) != 1 or actor.obs_dim != 0:
        raise ConfigError(
            f"Playing an rsl_rl CNN actor needs one image observation group and nothing else; its groups are {groups}."
        )
    (height, width), channels = actor.obs_dims_2d[0], actor.obs_channels_2d[0]
    return _ImageActor(actor.as_onnx()), (int(height), int(width), int(channels))
