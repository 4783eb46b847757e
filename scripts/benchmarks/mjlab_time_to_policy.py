"""Peer figure: mjlab 1.6's time to a policy, judged as `simlab bench solve` judges simlab's.

1. Train: mjlab's own `python -m mjlab.scripts.train TASK` in a subprocess, with the task's own
   agent config, dt and decimation; only the env count, iteration cap, save interval, logger and
   log root are set here. The process start is this script's clock just before it is launched.
2. Play, after training has ended (so playing takes nothing from training): every saved
   checkpoint, in mjlab's own play env (``load_env_cfg(task, play=True)``), ``--eval-envs`` (64)
   envs for ``--eval-seconds`` (5 s) with the deterministic policy, all from the same seeded
   initial states, judged by simlab's criterion for the same kind of task
   (``simlab/tasks/utils/criteria.py`` and the velocity tasks' ``criterion.py``):
   - cartpole: |pole angle| < 0.2 rad in >= 95 % of the env-steps (mjlab's ``hinge_1`` joint);
   - velocity: mean |v_xy command - v_xy| <= 0.25 m/s over the env-steps, falls included (mjlab's
     ``twist`` command against the base's ``root_link_lin_vel_b``, the error mjlab logs itself);
     the command ranges are the training env's (mjlab's play env widens them for Go1, simlab's
     play envs keep the training ranges);
   - G1 and H1 velocity: the humanoids' bar (simlab's ``biped_tracks_velocity``): mean planar speed
     error in the heading's frame < 0.25 m/s, yaw-rate error < 0.3 rad/s, < 5 % falls per env in
     20 s, played at least 20 s (mjlab's play env never times out, so its commands resample).
3. Time to policy: the first passing checkpoint's write time (its mtime) less the process start.
   Start-up: the process start to the first iteration (when rsl_rl printed iteration 0, less that
   iteration's collection and learning times). Rollout and update: rsl_rl's printed collection and
   learning times summed up to that checkpoint's iteration; the rest (saves, logging) is "other".

Run with mjlab on the path and in its own process (it brings its own MuJoCo), e.g. on the GPU host
    PYTHONPATH=/tmp/mjsite:/tmp/site python3 scripts/benchmarks/mjlab_time_to_policy.py \
        Mjlab-Cartpole-Balance --num-envs 4096 --max-iterations 150 --save-interval 10
and on a CPU (mjlab trains there when CUDA_VISIBLE_DEVICES is empty; ``--device cpu`` sets it)
    ... Mjlab-Cartpole-Balance --device cpu --num-envs 16 --max-iterations 3 --save-interval 1
This module imports mjlab only to play, so its parsing and criteria run without it.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import re
import subprocess
import sys
import time
from collections.abc import Iterable
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

# simlab's criteria (pole_upright, tracks_velocity, biped_tracks_velocity: registered with simlab's
# tasks); tested to agree.
POLE_ANGLE_RAD = 0.2
POLE_UPRIGHT_FRACTION = 0.95
VELOCITY_ERROR_M_S = 0.25
BIPED_SPEED_ERROR_M_S = 0.25
BIPED_YAW_RATE_ERROR_RAD_S = 0.3
BIPED_FALL_RATE = 0.05  # falls per env per 20 s

_ANSI = re.compile(r"\x1b\[[0-9;]*m")
_ITERATION = re.compile(r"Learning iteration (\d+)/(\d+)")
_COLLECTION = re.compile(r"Collection time:\s*([0-9.]+)s")
_LEARNING = re.compile(r"Learning time:\s*([0-9.]+)s")
_LOG_DIR = re.compile(r"Logging experiment in directory:\s*(\S+)")
_CHECKPOINT = re.compile(r"model_(\d+)\.pt$")


# -- what mjlab's training printed ----------------------------------------------------------------


@dataclass
class Iteration:
    """One rsl_rl iteration as its printed log shows it."""

    logged_at: float  # wall clock when its "Learning iteration" line arrived
    collection_s: float = math.nan
    learning_s: float = math.nan


@dataclass
class TrainingLog:
    run_dir: str | None = None
    iterations: dict[int, Iteration] = field(default_factory=dict)

    def startup_s(self, process_start: float) -> float:
        """Process start to the start of iteration 0 (NaN if none was printed)."""
        first = self.iterations.get(min(self.iterations, default=-1))
        if first is None:
            return math.nan
        return first.logged_at - process_start - first.collection_s - first.learning_s

    def shares_until(self, iteration: int) -> tuple[float, float]:
        """Summed collection and learning seconds of the iterations up to ``iteration``."""
        done = [it for i, it in self.iterations.items() if i <= iteration]
        return sum(it.collection_s for it in done), sum(it.learning_s for it in done)


def parse_training_output(lines: Iterable[tuple[float, str]]) -> TrainingLog:
    """Read mjlab's train output, given as (wall-clock arrival time, line) pairs."""
    log = TrainingLog()
    current: Iteration | None = None
    for arrived, raw in lines:
        line = _ANSI.sub("", raw)
        if match := _LOG_DIR.search(line):
            log.run_dir = match.group(1)
        elif match := _ITERATION.search(line):
            current = log.iterations.setdefault(int(match.group(1)), Iteration(logged_at=arrived))
        elif current is not None and (match := _COLLECTION.search(line)):
            current.collection_s = float(match.group(1))
        elif current is not None and (match := _LEARNING.search(line)):
            current.learning_s = float(match.group(1))
    return log


@dataclass
class Checkpoint:
    iteration: int  # rsl_rl's 0-based iteration after which it was saved
    path: str
    written_at: float  # mtime, wall clock


def find_checkpoints(run_dir: str | Path) -> list[Checkpoint]:
    """The run's ``model_<iteration>.pt`` files in iteration order."""
    found = []
    for path in Path(run_dir).iterdir():
        if match := _CHECKPOINT.search(path.name):
            found.append(Checkpoint(int(match.group(1)), str(path), path.stat().st_mtime))
    return sorted(found, key=lambda c: c.iteration)


# -- criteria: each reads the mjlab env after every played step -----------------------------------


def wrap_angle(angle):
    """An angle (tensor) in [-pi, pi)."""
    import torch

    return torch.remainder(angle + math.pi, 2 * math.pi) - math.pi


class PoleUpright:
    """|pole angle| < 0.2 rad in >= 95 % of the env-steps (score: that share)."""

    description = f"|pole angle| < {POLE_ANGLE_RAD} rad in >= {POLE_UPRIGHT_FRACTION:.0%} of env-steps"

    def __init__(self, joint_name: str = "hinge_1"):
        self.joint_name = joint_name
        self.inside = self.total = 0

    def observe(self, env: Any) -> None:
        angle = None
        for entity in env.scene.entities.values():
            if self.joint_name in entity.joint_names:
                angle = entity.data.joint_pos[:, entity.joint_names.index(self.joint_name)]
        if angle is None:
            raise RuntimeError(f"No entity with a '{self.joint_name}' joint in this task's scene.")
        self.inside += int((wrap_angle(angle).abs() < POLE_ANGLE_RAD).sum())
        self.total += angle.numel()

    def verdict(self) -> tuple[float, bool]:
        share = self.inside / max(1, self.total)
        return share, self.total > 0 and share >= POLE_UPRIGHT_FRACTION


class TracksVelocity:
    """Mean |v_xy command - v_xy| (base frame) <= 0.25 m/s over the env-steps (score: the error)."""

    description = f"mean |v_xy command - v_xy| <= {VELOCITY_ERROR_M_S} m/s"

    def __init__(self, command_name: str = "twist", entity_name: str = "robot"):
        self.command_name, self.entity_name = command_name, entity_name
        self.error = 0.0
        self.total = 0

    def observe(self, env: Any) -> None:
        import torch

        command = env.command_manager.get_command(self.command_name)[:, :2]
        velocity = env.scene[self.entity_name].data.root_link_lin_vel_b[:, :2]
        self.error += float(torch.linalg.norm(command - velocity, dim=-1).sum())
        self.total += command.shape[0]

    def verdict(self) -> tuple[float, bool]:
        error = self.error / max(1, self.total)
        return error, self.total > 0 and error <= VELOCITY_ERROR_M_S


class BipedTracksVelocity:
    """The humanoids' bar: mean planar speed error (yaw frame) < 0.25 m/s, yaw-rate error (world z) <
    0.3 rad/s, < 5 % falls per env in 20 s (score: the speed error); plays at least 20 s."""

    description = (
        f"mean |v_xy command - v_xy| < {BIPED_SPEED_ERROR_M_S} m/s, |yaw-rate error| < "
        f"{BIPED_YAW_RATE_ERROR_RAD_S} rad/s, < {BIPED_FALL_RATE:.0%} falls per env in 20 s"
    )
    min_seconds = 20.0

    def __init__(self, command_name: str = "twist", entity_name: str = "robot"):
        self.command_name, self.entity_name = command_name, entity_name
        self.speed = self.yaw_rate = self.seconds = 0.0
        self.falls = self.samples = self.steps = 0

    def observe(self, env: Any) -> None:
        import torch

        command = env.command_manager.get_command(self.command_name)
        data = env.scene[self.entity_name].data
        w, x, y, z = data.root_link_quat_w.unbind(-1)
        yaw = torch.atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))
        vx, vy = data.root_link_lin_vel_w[:, 0], data.root_link_lin_vel_w[:, 1]
        # the world velocity turned into the heading's frame, where the command lives
        velocity = torch.stack([yaw.cos() * vx + yaw.sin() * vy, -yaw.sin() * vx + yaw.cos() * vy], -1)
        self.speed += float(torch.linalg.norm(command[:, :2] - velocity, dim=-1).sum())
        self.yaw_rate += float((command[:, 2] - data.root_link_ang_vel_w[:, 2]).abs().sum())
        self.falls += int(env.termination_manager.terminated.sum())
        self.samples += command.shape[0]
        self.steps += 1
        self.seconds += env.step_dt

    def verdict(self) -> tuple[float, bool]:
        samples = max(1, self.samples)
        speed, yaw_rate = self.speed / samples, self.yaw_rate / samples
        fall_rate = self.falls / (samples / max(1, self.steps)) * 20.0 / max(self.seconds, 1e-9)
        tracks = speed < BIPED_SPEED_ERROR_M_S and yaw_rate < BIPED_YAW_RATE_ERROR_RAD_S
        return speed, self.samples > 0 and tracks and fall_rate < BIPED_FALL_RATE


def criterion_for(task: str) -> type[PoleUpright] | type[TracksVelocity] | type[BipedTracksVelocity]:
    if "Cartpole" in task:
        return PoleUpright
    if "Velocity" in task and any(robot in task for robot in ("-G1", "-H1")):
        return BipedTracksVelocity  # simlab's G1 and H1 velocity tasks register this one
    if "Velocity" in task:
        return TracksVelocity
    raise ValueError(f"No criterion for {task}: this script judges mjlab's Cartpole and Velocity tasks.")


# -- the two phases -------------------------------------------------------------------------------


def train_command(
    task: str, num_envs: int | None, max_iterations: int, save_interval: int, log_root: str, seed: int
) -> list[str]:
    """mjlab's train CLI (tyro flags of mjlab.scripts.train.TrainConfig)."""
    argv = [sys.executable, "-m", "mjlab.scripts.train", task]
    if num_envs is not None:
        argv += ["--env.scene.num-envs", str(num_envs)]
    argv += ["--agent.max-iterations", str(max_iterations), "--agent.save-interval", str(save_interval)]
    argv += ["--agent.logger", "tensorboard", "--agent.seed", str(seed), "--log-root", log_root]
    return argv


def child_environment(device: str) -> dict[str, str]:
    env = dict(os.environ, PYTHONUNBUFFERED="1")  # lines arrive when printed: their time is the log's clock
    env.setdefault("MUJOCO_GL", "disable")
    env.setdefault("WANDB_MODE", "disabled")
    if device == "cpu":
        env["CUDA_VISIBLE_DEVICES"] = ""  # mjlab's train runs on the CPU then
    return env


def run_training(argv: list[str], env: dict[str, str], cwd: str, log_path: str, budget_s: float | None):
    """Run mjlab's training; returns (process start, exit code, timestamped lines).

    ``budget_s`` ends it (SIGTERM) that many seconds after its start; what it saved is kept.
    """
    lines: list[tuple[float, str]] = []
    stopping = False
    start = time.time()
    with (
        open(log_path, "w") as log,
        subprocess.Popen(
            argv, cwd=cwd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, bufsize=1
        ) as process,
    ):
        assert process.stdout is not None
        for line in process.stdout:
            now = time.time()
            lines.append((now, line))
            log.write(line)
            if match := _ITERATION.search(_ANSI.sub("", line)):
                print(f"  [train {now - start:7.1f} s] iteration {match.group(1)}/{match.group(2)}", flush=True)
            if budget_s is not None and now - start > budget_s and process.poll() is None:
                if not stopping:
                    print(f"  [train] time budget {budget_s:.0f} s spent: stopping mjlab's training", flush=True)
                stopping = True
                if now - start < budget_s + 10:
                    process.terminate()
                else:  # it did not end on SIGTERM
                    process.kill()
        code = process.wait()
    return start, code, lines


def play_checkpoints(
    task: str, checkpoints: list[Checkpoint], device: str, eval_envs: int, eval_seconds: float, seed: int
) -> list[tuple[float, bool]]:
    """Play each checkpoint in mjlab's play env; one (score, passed) per checkpoint."""
    if not checkpoints:
        return []
    os.environ.setdefault("MUJOCO_GL", "disable")
    import mjlab.tasks  # noqa: F401  (registers mjlab's tasks)
    import torch
    from mjlab.envs import ManagerBasedRlEnv
    from mjlab.rl import MjlabOnPolicyRunner, RslRlVecEnvWrapper
    from mjlab.tasks.registry import load_env_cfg, load_rl_cfg, load_runner_cls

    criterion = criterion_for(task)
    env_cfg = load_env_cfg(task, play=True)
    env_cfg.scene.num_envs = eval_envs
    if criterion in (TracksVelocity, BipedTracksVelocity):  # judge within the ranges it trains on, as simlab does
        env_cfg.commands["twist"].ranges = load_env_cfg(task).commands["twist"].ranges
    agent_cfg = load_rl_cfg(task)
    env = RslRlVecEnvWrapper(ManagerBasedRlEnv(cfg=env_cfg, device=device), clip_actions=agent_cfg.clip_actions)
    runner = (load_runner_cls(task) or MjlabOnPolicyRunner)(env, asdict(agent_cfg), device=device)
    steps = max(1, round(eval_seconds / env.unwrapped.step_dt))
    verdicts = []
    try:
        for checkpoint in checkpoints:
            try:
                runner.load(checkpoint.path, load_cfg={"actor": True}, strict=True, map_location=device)
            except (RuntimeError, EOFError) as error:  # e.g. cut short by --train-seconds while written
                print(f"[mjlab] {checkpoint.path} does not load ({error}); counted as failing", flush=True)
                verdicts.append((math.nan, False))
                continue
            policy = runner.get_inference_policy(device=device)
            judge = criterion()
            env.unwrapped.seed(seed)  # every checkpoint from the same initial states
            torch.manual_seed(seed)
            obs, _ = env.reset()
            with torch.inference_mode():
                for _ in range(steps):
                    obs, _, _, _ = env.step(policy(obs))
                    judge.observe(env.unwrapped)
            verdicts.append(judge.verdict())
    finally:
        env.close()
    return verdicts


@dataclass
class Evaluated:
    checkpoint: Checkpoint
    score: float
    passed: bool


def summarize(
    task: str, process_start: float, log: TrainingLog, evaluated: list[Evaluated], num_envs: int | None
) -> dict[str, Any]:
    """The result row: time to policy with its shares, or the last checkpoint's figures if none passed."""
    solved = next((e for e in evaluated if e.passed), None)
    last = solved or (evaluated[-1] if evaluated else None)
    row: dict[str, Any] = {
        "task": task,
        "num_envs": num_envs,
        "solved": solved is not None,
        "startup_s": log.startup_s(process_start),
        "iterations_logged": len(log.iterations),
        "checkpoints": [
            {
                "file": os.path.basename(e.checkpoint.path),
                "iterations": e.checkpoint.iteration + 1,
                "written_at_s": e.checkpoint.written_at - process_start,
                "score": e.score,
                "passed": e.passed,
            }
            for e in evaluated
        ],
    }
    if last is not None:
        rollout, update = log.shares_until(last.checkpoint.iteration)
        at = last.checkpoint.written_at - process_start
        row.update(
            checkpoint=os.path.basename(last.checkpoint.path),
            iterations=last.checkpoint.iteration + 1,
            time_to_checkpoint_s=at,
            time_to_policy_s=at if solved else None,
            rollout_s=rollout,
            update_s=update,
            other_s=at - row["startup_s"] - rollout - update,
            score=last.score,
        )
    return row


def format_summary(row: dict[str, Any], criterion: str) -> str:
    head = f"mjlab {row['task']} ({row['num_envs'] or 'its own'} envs)"
    if "checkpoint" not in row:
        return f"{head}: no checkpoint was written; nothing to judge."
    shares = (
        f"start-up {row['startup_s']:.1f} s, rollout {row['rollout_s']:.1f} s, update {row['update_s']:.1f} s, "
        f"other {row['other_s']:.1f} s"
    )
    if row["solved"]:
        return (
            f"{head}: time to policy {row['time_to_policy_s']:.1f} s at {row['checkpoint']} "
            f"({row['iterations']} iterations, score {row['score']:.3f}); {shares}; criterion: {criterion}"
        )
    return (
        f"{head}: NOT solved; last checkpoint {row['checkpoint']} at {row['time_to_checkpoint_s']:.1f} s "
        f"({row['iterations']} iterations, score {row['score']:.3f}); {shares}; criterion: {criterion}"
    )


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("task", help="mjlab task id, e.g. Mjlab-Cartpole-Balance or Mjlab-Velocity-Flat-Unitree-Go1")
    parser.add_argument("--num-envs", type=int, default=4096, help="training envs (0: the task's own count)")
    parser.add_argument("--max-iterations", type=int, default=150)
    parser.add_argument("--save-interval", type=int, default=10, help="iterations between checkpoints")
    parser.add_argument("--train-seconds", type=float, default=None, help="stop training after this long")
    parser.add_argument("--device", default="cuda:0", help="cuda:0 or cpu")
    parser.add_argument("--eval-envs", type=int, default=64)
    parser.add_argument("--eval-seconds", type=float, default=5.0)
    parser.add_argument("--seed", type=int, default=42)
    parser.add_argument("--out", default=os.environ.get("OUT") or "mjlab_ttp", help="folder for logs and JSON")
    args = parser.parse_args(argv)
    criterion = criterion_for(args.task)  # fail before training on a task without a criterion
    if args.device != "cpu" and not args.device.startswith("cuda"):
        parser.error(f"--device {args.device}: use cpu or cuda:0 (mjlab's train takes the first visible GPU).")
    num_envs = args.num_envs or None

    out = Path(args.out).resolve() / args.task
    out.mkdir(parents=True, exist_ok=True)
    argv_train = train_command(
        args.task, num_envs, args.max_iterations, args.save_interval, str(out / "logs"), args.seed
    )
    print("training:", " ".join(argv_train[1:]), flush=True)
    start, code, lines = run_training(
        argv_train, child_environment(args.device), str(out), str(out / "train.log"), args.train_seconds
    )
    log = parse_training_output(lines)
    stopped = args.train_seconds is not None and code in (-15, 143)
    if code != 0 and not stopped:
        tail = "".join(line for _, line in lines[-30:])
        print(f"mjlab's training exited with code {code}; its output ends:\n{tail}", file=sys.stderr)
        return 1
    if log.run_dir is None:
        print(f"mjlab's training printed no log directory; see {out / 'train.log'}", file=sys.stderr)
        return 1
    checkpoints = find_checkpoints(log.run_dir)
    print(
        f"training ended {time.time() - start:.1f} s after its start; playing {len(checkpoints)} checkpoints",
        flush=True,
    )
    device = "cpu" if args.device == "cpu" else "cuda:0"
    playing = time.perf_counter()
    eval_seconds = max(args.eval_seconds, getattr(criterion, "min_seconds", 0.0))  # as simlab's play_seconds
    verdicts = play_checkpoints(args.task, checkpoints, device, args.eval_envs, eval_seconds, args.seed)
    if checkpoints:
        print(f"played {len(checkpoints)} checkpoints in {time.perf_counter() - playing:.1f} s", flush=True)
    evaluated = [Evaluated(c, s, p) for c, (s, p) in zip(checkpoints, verdicts, strict=True)]
    for e in evaluated:
        print(
            f"[mjlab] {os.path.basename(e.checkpoint.path)} ({e.checkpoint.iteration + 1} iterations) at "
            f"{e.checkpoint.written_at - start:.1f} s: score {e.score:.3f} {'PASS' if e.passed else 'fail'}",
            flush=True,
        )
    row = summarize(args.task, start, log, evaluated, num_envs)
    row.update(
        device=args.device,
        criterion=criterion.description,
        eval_envs=args.eval_envs,
        eval_seconds=eval_seconds,
        seed=args.seed,
        command=argv_train[1:],
    )
    (out / "result.json").write_text(json.dumps(row, indent=2))
    print(format_summary(row, criterion.description), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
