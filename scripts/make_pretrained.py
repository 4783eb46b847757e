"""Make the pretrained policies shipped in simlab/pretrained/ (``simlab play --use_pretrained_checkpoint``).

    python scripts/make_pretrained.py --tasks simlab/Ant-Direct-v0 simlab/Humanoid-Direct-v0 --device cuda:0
    python scripts/make_pretrained.py --tasks simlab/Cartpole-v0 --device cpu
    python scripts/make_pretrained.py --device cuda:0 --eval_every 25 --time_budget 125 \\
        --tasks simlab/Velocity-Flat-Unitree-Go2-v0 simlab/Velocity-Flat-Anymal-C-v0 simlab/Reach-Franka-v0
    python scripts/make_pretrained.py --device cuda:0 --num_envs 1024 --eval_every 30 \
        --tasks simlab/Cartpole-RGB-Camera-Direct-v0 --overrides env.frame_stack=2   # trained (and played) so
    python scripts/make_pretrained.py --list      # every task: its criterion, whether rsl_rl trains it, shipped?
    python scripts/make_pretrained.py --restore --tasks simlab/Reach-Franka-v0   # its policy.pt stored again
    python scripts/make_pretrained.py --device cuda:0 --time_budget 960 --tasks simlab/Velocity-Rough-Unitree-Go2-v0 \
        --overrides env.scene.terrain.terrain_generator.seed=42   # train and play on one generated terrain
    python scripts/make_pretrained.py --device cuda:0 --num_envs 4096 --time_budget 1120 --library skrl \
        --tasks simlab/Humanoid-AMP-Walk-Direct-v0 --overrides agent.agent.learning_rate=1.0e-4 \
        env.motion_file=<clip>.npz          # an AMP humanoid: the task's skrl AMP agent
    python scripts/make_pretrained.py --tasks simlab/Velocity-Rough-Unitree-Go2-v0 --checkpoint model_700.pt \
        --trained_by "..."                  # a policy trained elsewhere
    python scripts/make_pretrained.py --tasks simlab/Stack-Cube-Franka-IK-Abs-v0 --library bc \
        --checkpoint logs/bc/stack.pt --trained_by "..."   # a policy cloned from demonstrations

For each task, ``simlab train`` trains it in a child process (the task's registered agent config of
``--library``, rsl_rl by default; ``--num_envs``, ``--max_iterations``, ``--seed`` and the Hydra
``--overrides`` as ``simlab train`` takes them; ``--eval_every`` is rsl_rl's ``save_interval``,
rl_games' ``save_frequency``).
Its checkpoints are then played in order on the training device, up to the first one that meets
the task's criterion (registered with the task, ``success_criterion_entry_point``:
``simlab.tasks.utils.criteria``). That checkpoint is played again on the CPU (MuJoCo C,
``--cpu_eval_envs`` envs for ``--eval_seconds``), where ``--use_pretrained_checkpoint`` plays it
after install, and shipped only if it passes there too (if it does not, the later checkpoints are judged on).

Shipped into ``<out>/<task name>/<library>/``: the run's ``params/`` (the agent config, the command and
the run's description; not the resolved env config, ``env.yaml``: about 18 KB a policy, which the task's
registered config at the same commit and the overrides in the command rebuild), the
policy's weights in one file, ``policy.pt`` (:mod:`simlab.pretrained.weights`: what play loads, the
matrices as int8 rows, or float16 where int8's replay misses the criterion, its zip entries deflated;
no critic, no optimizer state, so training cannot resume from it; play makes
the ONNX and TorchScript exports wherever it plays it), and ``record.json``: this script's command,
the training command, seed, iterations, device, the observation terms of each group in the order the
policy read them (``observations``, manager-based tasks), the criterion and its value on both devices (the CPU
replay plays the stored weights, as ``--use_pretrained_checkpoint`` will), the files' sizes, the
``env.*`` overrides of
``--overrides`` (``env_overrides``), which ``simlab play --use_pretrained_checkpoint`` applies too,
and after ``--resume`` the checkpoint it went on from and the command that trained that one.

A batch of tasks trains one after the other; ``--time_budget`` caps each task's training (its
process is stopped there and saves the iteration it is at, which is judged as any checkpoint and
shipped when it solves the task; else the ``SKIPPED`` line names that checkpoint when ``--log_root``
keeps it, and ``--resume PATH`` trains on from it). A task that
fails (not solved in its iterations or budget, failed on the CPU, a checkpoint whose play raised,
say on NaN observations, or another error) is skipped with one ``SKIPPED`` line saying why, and the
next one trains.
Every task must have a criterion and a config of ``--library``, checked before any training starts. The
script exits with 1 when a task was not shipped.

``--restore`` stores shipped policies again, from their own ``policy.pt``, when the stored forms
improve (:mod:`simlab.pretrained.weights`): the smallest form whose CPU replay, with the envs, seconds
and seed of the record's ``cpu_evaluation``, passes; the record keeps how the policy was trained.

``--checkpoint PATH`` ships a policy trained elsewhere (one task; a checkpoint of the task's agent for
``--library``, e.g. an AMP humanoid's ``agent_<timestep>.pt`` with ``--library skrl``) without
training: its run folder is written from the task's registered configs, and it is judged on
the CPU only; ``--trained_by`` says in ``record.json`` how it was trained. A behaviour-cloned policy
(``scripts/imitation_learning/bc.py train``; the task registers ``bc_cfg_entry_point``) ships this way
with ``--library bc``.
"""

from __future__ import annotations

import argparse
import datetime
import glob
import json
import os
import re
import shlex
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from typing import Any

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
LIBRARY = "rsl_rl"  # the default library (--library)
# the agent setting that --eval_every sets: iterations (rl_games: epochs) between saved checkpoints
EVAL_EVERY = {"rsl_rl": "agent.save_interval", "rl_games": "agent.params.config.save_frequency"}


def parse_args(argv: list[str] | None = None) -> argparse.Namespace:
    from simlab.pretrained import PRETRAINED_DIR
    from simlab.pretrained.weights import PLAY_KEYS

    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--tasks", nargs="+", default=None, help="Gymnasium ids of the tasks to train and ship.")
    parser.add_argument("--list", action="store_true", help="List every task: criterion, rsl_rl config, shipped.")
    parser.add_argument(
        "--time_budget", type=float, default=None, help="Seconds of training per task before it is skipped."
    )
    parser.add_argument("--device", default="cpu", help="Where to train: cpu or cuda:N.")
    parser.add_argument("--num_envs", type=int, default=None, help="Training envs (default: the task's).")
    parser.add_argument("--max_iterations", type=int, default=None, help="Give up after (default: the agent's).")
    parser.add_argument("--eval_every", type=int, default=None, help="Iterations between evaluated checkpoints.")
    parser.add_argument("--seed", type=int, default=42, help="Training and evaluation seed.")
    parser.add_argument("--eval_envs", type=int, default=64, help="Envs that play each checkpoint while training.")
    parser.add_argument("--cpu_eval_envs", type=int, default=32, help="Envs of the final play on the CPU.")
    parser.add_argument("--eval_seconds", type=float, default=5.0, help="Seconds of play per evaluation.")
    parser.add_argument(
        "--reward_threshold", type=float, default=None, help="Judge by this mean reward per step instead."
    )
    parser.add_argument("--out", default=PRETRAINED_DIR, help="Where the policies go (default: the package's).")
    parser.add_argument("--log_root", default=None, help="Keep the training runs here (default: a temporary folder).")
    parser.add_argument("--checkpoint", default=None, help="Ship this checkpoint, no training (one task).")
    parser.add_argument(
        "--restore",
        action="store_true",
        help="Store the shipped policies of --tasks again from their own policy.pt, in the smallest form whose"
        " CPU replay (record.json's) passes; no training",
    )
    parser.add_argument(
        "--resume", default=None, help="Train on from this checkpoint (one task), e.g. one a time budget stopped."
    )
    parser.add_argument(
        "--library",
        choices=sorted(PLAY_KEYS),
        default=LIBRARY,
        help="The library that trains (its registered agent config) or wrote --checkpoint.",
    )
    parser.add_argument("--trained_by", default=None, help="With --checkpoint: how it was trained, for record.json.")
    parser.add_argument(
        "--agent",
        default=None,
        help="The task's agent config to train and play with (its registry key, e.g."
        " rsl_rl_distillation_cfg_entry_point; default: the library's); kept in record.json, play uses it",
    )
    parser.add_argument(
        "--teacher",
        default=None,
        help="With a distillation --agent: the teacher's checkpoint (or run folder) the student learns from;"
        " named in record.json",
    )
    parser.add_argument(
        "--overrides",
        nargs="+",
        default=[],
        help="env.* / agent.* overrides to train with (e.g. env.frame_stack=2); the env.* ones are kept in"
        " record.json and play applies them to the shipped policy",
    )
    args = parser.parse_args(argv)
    if not args.list and not args.tasks:
        parser.error("give --tasks ID [ID ...] (or --list to see the tasks)")
    if args.library == "bc" and args.checkpoint is None and not args.list:
        parser.error(
            "--library bc ships a policy cloned from demonstrations: give the --checkpoint that"
            " scripts/imitation_learning/bc.py train wrote"
        )
    if args.teacher is not None and (args.agent is None or args.resume is not None):
        parser.error("--teacher is the checkpoint a distillation --agent learns from: give --agent, and not --resume")
    if args.restore and (args.checkpoint is not None or args.resume is not None):
        parser.error("--restore stores shipped policies again from their policy.pt: no --checkpoint or --resume")
    if args.checkpoint is not None:
        if len(args.tasks or []) != 1:
            parser.error("--checkpoint ships one policy: give exactly one task with --tasks")
        if not os.path.isfile(args.checkpoint):
            parser.error(f"--checkpoint {args.checkpoint}: no such file")
        if not args.trained_by:
            parser.error("--checkpoint needs --trained_by: how the policy was trained (kept in record.json)")
    elif args.resume is not None and (len(args.tasks or []) != 1 or not os.path.isfile(args.resume)):
        parser.error(f"--resume {args.resume}: give one task with --tasks and an existing checkpoint file")
    if args.eval_every is not None and args.library not in EVAL_EVERY:
        parser.error(
            "--eval_every sets rsl_rl's save_interval or rl_games' save_frequency; with skrl give its"
            " checkpoint_interval in --overrides (SB3 saves every 50 rollouts)"
        )
    # Hydra's +key=value adds a key the config lacks (e.g. +agent.normalize_input=true)
    bad = [o for o in args.overrides if not o.lstrip("+").startswith(("env.", "agent.")) or "=" not in o]
    if bad:
        parser.error(f"--overrides {' '.join(bad)}: each looks like env.x.y=1 or agent.z=2")
    return args


def env_overrides(args: argparse.Namespace) -> list[str]:
    """The overrides that change the env (the trained policy needs them wherever it plays)."""
    from simlab.tasks.utils.hydra import env_overrides_in

    return env_overrides_in(args.overrides)


class OverBudget(RuntimeError):
    """Training did not solve the task within ``--time_budget``."""


class JudgeFailed(RuntimeError):
    """Playing a checkpoint to judge it raised (a policy that drives the env to NaN, say)."""


def judge_one(judge: Any, checkpoint: str, iteration: int) -> None:
    """Play ``checkpoint`` with ``judge`` (a :class:`~simlab.benchmarks.solve.CheckpointJudge`); an error
    while it plays becomes a one-line :class:`JudgeFailed` naming the checkpoint, which skips the task,
    not the batch. simlab's own errors (no OpenGL here, say) pass as they are: they already say what to do."""
    from simlab.utils.errors import SimlabError

    try:
        judge(checkpoint, iteration, {"rollout": 0.0, "update": 0.0})
    except SimlabError:
        raise
    except Exception as e:  # whatever the env or the policy raised: the cause stays chained
        first_line = (str(e).strip().splitlines() or [""])[0]
        raise JudgeFailed(f"judging {checkpoint} failed: {type(e).__name__}: {first_line}") from e


SAVE_GRACE_S = 120.0  # how long a training stopped by the budget may take to save its checkpoint
# The training's run folder: <log_root>/<library>/<experiment>/<time>_<pid>_make_pretrained. The
# process id keeps two make_pretrained processes sharing a log root (on one GPU) from judging each
# other's checkpoints.
RUN_NAME = f"{os.getpid()}_make_pretrained"


def stop_and_save(child: subprocess.Popen, log_root: str, started: float) -> str | None:
    """Stop the training at the budget; the checkpoint it saved on the way out, if any.

    SIGTERM reaches ``simlab train`` as Ctrl+C does (it saves the iteration it is at); a training
    that has not saved within ``SAVE_GRACE_S`` is killed.
    """
    os.killpg(child.pid, signal.SIGTERM)
    try:
        child.wait(timeout=SAVE_GRACE_S)
    except subprocess.TimeoutExpired:
        os.killpg(child.pid, signal.SIGKILL)
        child.wait()
    return newest_checkpoint(log_root, started)


def run_checkpoints(log_root: str, started: float) -> list[str]:
    """The checkpoints this script's training under ``log_root`` wrote since ``started`` (a
    time.time()), oldest first, whatever the library."""
    from simlab.cli.runs import CHECKPOINT_LAYOUT, is_checkpoint_name

    found = []
    for library, (folder, _) in CHECKPOINT_LAYOUT.items():
        for run_dir in glob.glob(os.path.join(log_root, library, "*", f"*_{RUN_NAME}")):
            where = os.path.join(run_dir, *folder)
            names = os.listdir(where) if os.path.isdir(where) else []
            found += [os.path.join(where, n) for n in names if is_checkpoint_name(n, library)]
    saved = [p for p in found if os.path.getmtime(p) >= started]
    return sorted(saved, key=os.path.getmtime)


def newest_checkpoint(log_root: str, started: float) -> str | None:
    """The newest checkpoint a training under ``log_root`` wrote since ``started`` (a time.time())."""
    saved = run_checkpoints(log_root, started)
    return saved[-1] if saved else None


def over_budget_text(task: str, args: argparse.Namespace, saved: str | None) -> str:
    return f"not solved within the time budget of {args.time_budget:g} s" + kept_text(task, args, saved)


def kept_text(task: str, args: argparse.Namespace, saved: str | None) -> str:
    """What a stopped training kept (``saved``, its last checkpoint) and the commands that go on from it."""
    if saved is None:
        return " (no checkpoint written)"
    if args.log_root is None:
        return " (its last checkpoint was in a temporary folder: give --log_root to keep it)"
    train_on = script_command(task, args, "--resume", saved, "--device", args.device, *run_setting_flags(task, args))
    ship = script_command(task, args, "--checkpoint", saved, "--trained_by", "...")
    return f"; its last checkpoint is {saved}: train on with `{train_on}`, or judge and ship it as it is with `{ship}`"


# what a training and its judging were given, which the command that trains on from it keeps (a chunked
# training: the same envs, budget, checkpoint interval and run folder each time)
RUN_SETTINGS = (
    "num_envs", "max_iterations", "time_budget", "eval_every", "eval_envs", "eval_seconds", "cpu_eval_envs",
    "seed", "log_root",
)  # fmt: skip


def run_setting_flags(task: str, args: argparse.Namespace) -> list[str]:
    """``args``' ``RUN_SETTINGS`` that differ from this script's defaults, as flags."""
    defaults = parse_args(["--tasks", task])
    flags = []
    for name in RUN_SETTINGS:
        value = getattr(args, name)
        if value != getattr(defaults, name):
            flags += [f"--{name}", f"{value:g}" if isinstance(value, float) else str(value)]
    return flags


def script_command(task: str, args: argparse.Namespace, *flags: str) -> str:
    """This script's command line for ``task`` with ``flags``, keeping the run's library and ``--overrides``."""
    command = ["python", "scripts/make_pretrained.py", "--tasks", task, *flags]
    command += ["--library", args.library] if args.library != LIBRARY else []
    command += ["--agent", args.agent] if args.agent else []
    command += ["--overrides", *args.overrides] if args.overrides else []
    return shlex.join(command)


def train_command(task: str, args: argparse.Namespace, log_root: str) -> list[str]:
    """``simlab train`` for ``task``: the task's registered agent config of ``--library``, with this
    script's seed, sizes and ``--overrides`` (Hydra overrides, as ``simlab train`` takes them)."""
    command = [sys.executable, "-m", "simlab", "train", "--task", task, "--library", args.library, "--headless"]
    command += ["--device", args.device, "--seed", str(args.seed), "--log_root", log_root, "--run_name", RUN_NAME]
    for flag in ("num_envs", "max_iterations"):
        if getattr(args, flag) is not None:
            command += [f"--{flag}", str(getattr(args, flag))]
    if args.resume is not None:
        command += ["--checkpoint", args.resume]
    if args.agent is not None:
        command += ["--agent", args.agent]
    if args.teacher is not None:  # simlab train's --checkpoint of a distillation: the teacher
        command += ["--checkpoint", args.teacher]
    if args.eval_every is not None:  # parse_args allows it for the libraries of EVAL_EVERY only
        command.append(f"{EVAL_EVERY[args.library]}={args.eval_every}")
    return command + list(args.overrides)


def judge_checkpoints(task: str, args: argparse.Namespace, checkpoints: list[str], started: float) -> dict[str, Any]:
    """Play the training's checkpoints in order on the training device, up to the first that meets the
    task's criterion; the result row (``solved``, ``evaluations``, ``run_dir``, ...)."""
    from simlab.benchmarks.solve import CheckpointJudge
    from simlab.cli.runs import run_dir_of_checkpoint
    from simlab.utils.io import load_yaml

    run_dir = run_dir_of_checkpoint(checkpoints[-1], args.library)
    agent_cfg = load_yaml(os.path.join(run_dir, "params", "agent.yaml"))
    num_envs = load_yaml(os.path.join(run_dir, "params", "env.yaml"))["scene"]["num_envs"]
    judge = CheckpointJudge(
        task, args.library, args.device, args.eval_envs, args.eval_seconds, args.seed, args.reward_threshold,
        env_overrides(args), args.agent,
    )  # fmt: skip
    try:
        for checkpoint in checkpoints:
            iteration = checkpoint_iteration(checkpoint, args.library, agent_cfg)
            try:
                judge_one(judge, checkpoint, iteration)
            except JudgeFailed as e:  # say what the training kept and how to go on from it
                raise JudgeFailed(str(e) + kept_text(task, args, checkpoints[-1])) from e
            judge.evaluations[-1]["time_to_checkpoint_s"] = os.path.getmtime(checkpoint) - started
            print(f"[make_pretrained] {os.path.basename(checkpoint)}: {judge.evaluations[-1]['score']:.3f}", flush=True)
            if judge.evaluations[-1]["passed"]:
                break
    finally:
        judge.close()
    last = judge.evaluations[-1]
    return {
        "solved": last["passed"],
        "iteration": last["iteration"],
        "score": last["score"],
        "criterion": judge.criterion.description,
        "evaluations": judge.evaluations,
        "run_dir": run_dir,
        "num_envs": num_envs,
    }


def train_until_solved(task: str, args: argparse.Namespace, log_root: str) -> dict[str, Any]:
    """``simlab train`` for ``task`` in a child process (stopped at ``--time_budget``), then its
    checkpoints judged in order; the result row."""
    from simlab.cli.main import EXIT_TERMINATED

    command = train_command(task, args, log_root)
    print(f"[make_pretrained] {shlex.join(command)}", flush=True)
    started = time.time()
    # its own process group: the budget stops the training process and anything it started
    child = subprocess.Popen(command, cwd=REPO, start_new_session=True)
    over_budget = False
    try:
        code = child.wait(timeout=args.time_budget)
    except subprocess.TimeoutExpired:
        stop_and_save(child, log_root, started)
        over_budget = True
    else:
        if code in (-signal.SIGTERM, EXIT_TERMINATED):  # someone else stopped it: say what it kept
            raise RuntimeError(
                "training was stopped by a SIGTERM" + kept_text(task, args, newest_checkpoint(log_root, started))
            )
        if code != 0:
            raise RuntimeError(f"training exited with status {code} (its output is above)")
    checkpoints = run_checkpoints(log_root, started)
    if not checkpoints:
        if over_budget:
            raise OverBudget(over_budget_text(task, args, None))
        raise RuntimeError(f"training {task} wrote no checkpoint under {log_root}")
    row = judge_checkpoints(task, args, checkpoints, started)
    if over_budget and not row["solved"]:
        raise OverBudget(over_budget_text(task, args, checkpoints[-1]))
    return {**row, "checkpoints": checkpoints, "started": started}


def evaluate_on_cpu(task: str, checkpoint: str, iteration: int, args: argparse.Namespace) -> dict[str, Any]:
    """Play ``checkpoint`` on the CPU (MuJoCo C) and judge it by the task's criterion."""
    from simlab.benchmarks.solve import CheckpointJudge

    judge = CheckpointJudge(
        task,
        args.library,
        "cpu",
        args.cpu_eval_envs,
        args.eval_seconds,
        args.seed,
        args.reward_threshold,
        env_overrides(args),
        args.agent,
    )
    seconds = judge.criterion.play_seconds(args.eval_seconds)
    try:
        judge_one(judge, checkpoint, iteration)
    finally:
        judge.close()
    (entry,) = judge.evaluations
    return {
        "device": "cpu",
        "envs": args.cpu_eval_envs,
        "seconds": seconds,
        "seed": args.seed,
        "score": entry["score"],
        "passed": entry["passed"],
    }


def stage(task: str, checkpoint: str, library: str, log_root: str, matrices: str) -> str:
    """Write the shipped form of ``checkpoint`` (its matrices as ``matrices``) into
    ``<log_root>/stored/<task name>/<library>/`` (the run's ``params/`` and ``policy.pt``) and beside it
    the checkpoint play will make of it; returns that checkpoint, which the CPU replay plays."""
    from simlab.cli.runs import CHECKPOINT_LAYOUT, run_dir_of_checkpoint
    from simlab.pretrained import POLICY_FILE
    from simlab.pretrained.weights import pack_policy, read_checkpoint, save_policy, unpack_policy, write_checkpoint

    run_dir = run_dir_of_checkpoint(checkpoint, library)
    staged = os.path.join(log_root, "stored", task.split("/")[-1], library)
    shutil.rmtree(staged, ignore_errors=True)
    shutil.copytree(os.path.join(run_dir, "params"), os.path.join(staged, "params"))
    name = os.path.join(*CHECKPOINT_LAYOUT[library][0], os.path.basename(checkpoint))  # skrl's: checkpoints/
    state = read_checkpoint(checkpoint, library)  # weights only: a run's file is data
    save_policy(pack_policy(state, library, name, matrices), os.path.join(staged, POLICY_FILE))
    name, played = unpack_policy(os.path.join(staged, POLICY_FILE))
    os.makedirs(os.path.dirname(os.path.join(staged, name)), exist_ok=True)
    write_checkpoint(played, os.path.join(staged, name), library)
    return os.path.join(staged, name)


def stage_and_replay(
    task: str, checkpoint: str, iteration: int, args: argparse.Namespace, log_root: str
) -> tuple[str, dict[str, Any], str]:
    """Stage ``checkpoint`` in the smallest stored form (:data:`simlab.pretrained.weights.MATRICES`)
    whose CPU replay meets the criterion; (staged checkpoint, CPU evaluation, form). When none does,
    the last form tried, which failed."""
    from simlab.pretrained.weights import MATRICES

    for matrices in MATRICES:
        staged = stage(task, checkpoint, args.library, log_root, matrices)
        cpu = evaluate_on_cpu(task, staged, iteration, args)
        print(f"[make_pretrained] {task} stored as {matrices}: {cpu['score']:.3f} on the CPU", flush=True)
        if cpu["passed"]:
            break
    return staged, cpu, matrices


UNSHIPPED_PARAMS = "env.yaml"  # the resolved env config: rebuilt from the task and the command


def observation_terms(env_yaml: str) -> dict[str, list[str]]:
    """``{group: [term, ...]}`` of a manager-based run's ``params/env.yaml``, in the order its groups
    concatenate them; empty for a direct task (no observation manager)."""
    from simlab.utils.io import load_yaml

    groups = load_yaml(env_yaml).get("observations") or {}
    return {
        group: [name for name, term in cfg.items() if isinstance(term, dict) and "func" in term]
        for group, cfg in groups.items()
        if isinstance(cfg, dict)
    }


def ship(task: str, staged_checkpoint: str, record: dict[str, Any], out: str) -> str:
    """Copy the staged run (:func:`stage`) into ``out``, less the checkpoint play makes of ``policy.pt``."""
    from simlab.cli.runs import run_dir_of_checkpoint
    from simlab.pretrained import POLICY_FILE

    library = record["library"]
    staged = run_dir_of_checkpoint(staged_checkpoint, library)
    target = os.path.join(out, task.split("/")[-1], library)
    shutil.rmtree(target, ignore_errors=True)
    params = os.path.join(staged, "params")
    shutil.copytree(params, os.path.join(target, "params"), ignore=shutil.ignore_patterns(UNSHIPPED_PARAMS))
    observations = observation_terms(os.path.join(params, UNSHIPPED_PARAMS))
    if observations:
        record["observations"] = observations
    shutil.copy2(os.path.join(staged, POLICY_FILE), target)
    files = [os.path.join(root, name) for root, _, names in os.walk(target) for name in names]
    record["files_bytes"] = {os.path.relpath(f, target): os.path.getsize(f) for f in sorted(files)}
    with open(os.path.join(target, "record.json"), "w") as f:
        json.dump(record, f, indent=2)
        f.write("\n")
    return target


def run_command(run_dir: str) -> str:
    """The command that trained the run in ``run_dir`` (its ``params/command.txt``, as simlab writes it)."""
    with open(os.path.join(run_dir, "params", "command.txt")) as f:
        return f.read().strip()


def resumed_run_command(checkpoint: str) -> str | None:
    """The command that trained ``checkpoint``, if its run folder is there with it."""
    run_dir = os.path.dirname(os.path.abspath(checkpoint))
    return run_command(run_dir) if os.path.isfile(os.path.join(run_dir, "params", "command.txt")) else None


def record_header(task: str, args: argparse.Namespace, argv: list[str]) -> dict[str, Any]:
    """The fields of ``record.json`` that say what was shipped and by which command, when, and the env
    overrides play must apply to it."""
    header: dict[str, Any] = {
        "task": task,
        "library": args.library,  # rsl_rl when this script trained it (parse_args sees to that)
        "made_by": shlex.join(["python", "scripts/make_pretrained.py", *argv]),
        "date": datetime.date.today().isoformat(),
    }
    if args.agent:  # play --use_pretrained_checkpoint loads the policy with this agent config
        header["agent"] = args.agent
    if args.teacher:
        header["teacher"] = args.teacher
    if args.resume:
        header["resumed_from"] = args.resume
        earlier = resumed_run_command(args.resume)
        if earlier:  # the checkpoint's path is machine-local; how it was trained is what stays meaningful
            header["resumed_from_command"] = earlier
    trained_with = env_overrides(args)
    if trained_with:
        header["env_overrides"] = trained_with
    return header


def make_one(task: str, args: argparse.Namespace, log_root: str, argv: list[str]) -> str | None:
    """Train, judge and ship ``task``; None when shipped, else why not."""
    from simlab.tasks.utils.criteria import criterion_for
    from simlab.utils.errors import SimlabError

    start = time.perf_counter()
    row = train_until_solved(task, args, log_root)
    missed_on_cpu = ""  # a checkpoint that passed on the training device, not in its CPU replay
    while True:
        if not row["solved"]:
            score = f"{row['criterion']}: {row['score']:.3f}"
            return f"{missed_on_cpu}not solved in {row['iteration'] + 1} iterations ({score})"
        solved = next(e for e in row["evaluations"] if e["passed"])
        try:
            staged, cpu, matrices = stage_and_replay(task, solved["checkpoint"], solved["iteration"], args, log_root)
        except JudgeFailed as e:  # the stored weights played and raised on the CPU (NaN observations, say)
            raise JudgeFailed(
                f"{os.path.basename(solved['checkpoint'])} passed on {args.device} ({solved['score']:.3f}), but {e}"
            ) from e
        except (RuntimeError, SimlabError) as e:  # e.g. a camera task on a host without OpenGL
            raise RuntimeError(
                f"{os.path.basename(solved['checkpoint'])} passed on {args.device} ({solved['score']:.3f}), but its"
                f" CPU replay failed here ({e}). Ship it from a machine where the replay runs:"
                f" {script_command(task, args, '--checkpoint', solved['checkpoint'], '--trained_by', '...')}"
            ) from e
        # a score at the criterion's edge can pass one replay and miss the other: judge on from the next checkpoint
        later = row["checkpoints"][row["checkpoints"].index(solved["checkpoint"]) + 1 :]
        if cpu["passed"] or not later:
            break
        missed_on_cpu = (
            f"{os.path.basename(solved['checkpoint'])} passed on {args.device} ({solved['score']:.3f}) but not on the"
            f" CPU ({cpu['score']:.3f}); the later checkpoints: "
        )
        print(f"[make_pretrained] {missed_on_cpu}judged next", flush=True)
        judged = judge_checkpoints(task, args, later, row["started"])
        row = {**judged, "checkpoints": later, "started": row["started"]}
    record = {
        **record_header(task, args, argv),
        "train_command": run_command(row["run_dir"]),
        "device": args.device,
        "num_envs": row["num_envs"],
        "seed": args.seed,
        "iterations": solved["iteration"] + 1,
        "checkpoint": os.path.basename(solved["checkpoint"]),
        "train_seconds": round(solved["time_to_checkpoint_s"], 1),
        "criterion": row["criterion"],
        "evaluation": {
            "device": args.device,
            "envs": args.eval_envs,
            "seconds": criterion_for(task, args.reward_threshold).play_seconds(args.eval_seconds),
            "score": solved["score"],
            "passed": True,
        },
        "cpu_evaluation": cpu,  # of the stored weights, as play will load them
        "weights": matrices,
    }
    if args.reward_threshold is not None:
        record["reward_threshold"] = args.reward_threshold
    if args.time_budget is not None:
        record["time_budget_s"] = args.time_budget
    if not cpu["passed"]:
        print(json.dumps(record, indent=2))
        return f"passed on {args.device} ({solved['score']:.3f}) but not on the CPU ({cpu['score']:.3f})"
    target = ship(task, staged, record, args.out)
    took = time.perf_counter() - start
    sizes = ", ".join(f"{name} {size / 1024:.0f} KiB" for name, size in record["files_bytes"].items())
    print(
        f"[make_pretrained] {task}: shipped in {target} after {record['iterations']} iterations"
        f" ({row['criterion']}: {solved['score']:.3f} on {args.device}, {cpu['score']:.3f} on the CPU;"
        f" {took:.0f} s); {sizes}",
        flush=True,
    )
    return None


def checkpoint_iteration(checkpoint: str, library: str, agent_cfg: dict) -> int:
    """The training iteration a checkpoint was saved after, counted from 0 as rsl_rl's ``model_<iter>.pt``
    (``record.json``'s ``iterations`` is this + 1): rsl_rl stores it; skrl names the timestep, and
    ``agent_<T>.pt`` is written after T steps, which held T // rollouts updates; SB3 stores its
    timesteps (a rollout is n_steps of every env); a BC policy its epochs; rl_games the epochs done."""
    from simlab.pretrained.weights import read_checkpoint
    from simlab.utils.trust import torch_load

    if library == "rsl_rl":
        return int(torch_load(checkpoint, map_location="cpu").get("iter", 0))
    if library == "bc":  # the epochs of its fit (bc.py writes them)
        from simlab.rl.bc import load_bc_policy

        load_bc_policy(checkpoint)  # a file that is not a BC policy: one-line CheckpointError, not AttributeError
        return max(0, int(torch_load(checkpoint, map_location="cpu").get("epochs") or 1) - 1)
    if library == "rl_games":  # epoch 1 is written after the first update
        return max(0, int(torch_load(checkpoint, map_location="cpu").get("epoch", 1)) - 1)
    if library == "sb3":
        data = read_checkpoint(checkpoint, library)["data"]
        return max(0, int(data["num_timesteps"]) // (int(data["n_steps"]) * int(data["n_envs"])) - 1)
    timestep = re.search(r"(\d+)\.pt$", os.path.basename(checkpoint))
    return max(0, int(timestep.group(1)) // agent_cfg["agent"]["rollouts"] - 1) if timestep else 0


def checkpoint_name(checkpoint: str, library: str, iteration: int, agent_cfg: dict) -> str:
    """A file name that play's checkpoint search finds (a script of the user's may save ``model_final.pt``)."""
    from simlab.cli.runs import is_checkpoint_name

    name = os.path.basename(checkpoint)
    if is_checkpoint_name(name, library):
        return name
    if library == "rsl_rl":
        return f"model_{iteration}.pt"
    if library == "rl_games":
        return f"last_ep_{iteration + 1}.pth"  # after iteration + 1 epochs
    return f"agent_{(iteration + 1) * agent_cfg['agent']['rollouts']}.pt"  # after iteration + 1 rollouts


def adopt_checkpoint(task: str, args: argparse.Namespace, log_root: str, argv: list[str]) -> str | None:
    """Judge ``args.checkpoint`` on the CPU and ship it; None when shipped, else why not."""
    import gymnasium as gym

    from simlab.cli.checkpoints import env_sizes
    from simlab.cli.main import build_parser
    from simlab.cli.runs import CHECKPOINT_LAYOUT, dump_params, write_run_info
    from simlab.cli.session import load_configs
    from simlab.tasks.utils.criteria import criterion_for

    # the task's registered configs as play loads them (skrl on an AMP-only task: its AMP agent)
    play_argv = ["play", "--task", task, "--library", args.library, "--device", "cpu"]
    play_args = build_parser().parse_args(play_argv + (["--agent", args.agent] if args.agent else []))
    env_cfg, agent_cfg = load_configs(play_args, env_overrides(args))
    algorithm = agent_cfg["agent"]["class"] if args.library == "skrl" else {"bc": "BC"}.get(args.library, "PPO")
    if getattr(agent_cfg, "class_name", None) == "DistillationRunner":
        algorithm = "Distillation"
    iteration = checkpoint_iteration(args.checkpoint, args.library, agent_cfg)
    # a run folder as simlab train writes it: the configs, run.yaml, the checkpoint in its library's place
    run_dir = os.path.join(log_root, "adopted", task.split("/")[-1])
    env_cfg.scene.num_envs = 1
    env = gym.make(task, cfg=env_cfg)
    try:
        sizes = env_sizes(env)
    finally:
        env.close()
    if args.num_envs is not None:
        env_cfg.scene.num_envs = args.num_envs
    dump_params(run_dir, env_cfg, agent_cfg, ["python", "scripts/make_pretrained.py", *argv])
    write_run_info(run_dir, {"task": task, "library": args.library, "algorithm": algorithm, **sizes})
    folder = os.path.join(run_dir, *CHECKPOINT_LAYOUT[args.library][0])
    os.makedirs(folder, exist_ok=True)
    checkpoint = os.path.join(folder, checkpoint_name(args.checkpoint, args.library, iteration, agent_cfg))
    shutil.copy2(args.checkpoint, checkpoint)
    staged, cpu, matrices = stage_and_replay(task, checkpoint, iteration, args, log_root)
    record = {
        **record_header(task, args, argv),
        "algorithm": algorithm,
        "trained_by": args.trained_by,
        "seed": args.seed,
        "iterations": iteration + 1,
        "checkpoint": os.path.basename(checkpoint),
        "criterion": criterion_for(task, args.reward_threshold).description,
        "cpu_evaluation": cpu,  # of the stored weights, as play will load them
        "weights": matrices,
    }
    if not cpu["passed"]:
        print(json.dumps(record, indent=2))
        return f"failed on the CPU ({cpu['score']:.3f})"
    target = ship(task, staged, record, args.out)
    print(f"[make_pretrained] {task}: shipped in {target} ({record['criterion']}: {cpu['score']:.3f} on the CPU)")
    return None


def restore(task: str, args: argparse.Namespace, log_root: str, argv: list[str]) -> str | None:
    """Store the shipped ``task`` policy of ``--library`` in ``--out`` again from its own ``policy.pt``
    (when the stored forms improve): the smallest form whose CPU replay, as its record ran it, passes.
    Its record keeps how it was trained; ``weights``, ``cpu_evaluation`` and the file's size are the new
    file's, ``weights_note`` says what changed. None when stored again, else why not."""
    from simlab.pretrained import POLICY_FILE
    from simlab.pretrained.weights import unpack_policy, write_checkpoint

    shipped = os.path.join(args.out, task.split("/")[-1], args.library)
    record_path = os.path.join(shipped, "record.json")
    if not os.path.isfile(record_path):
        return f"no shipped {args.library} policy with a record.json in {shipped}"
    with open(record_path) as f:
        record = json.load(f)
    # the play that judged it when it shipped: its envs, seconds, seed, env overrides and agent config
    replay = record["cpu_evaluation"]
    args = argparse.Namespace(**vars(args))
    args.cpu_eval_envs, args.eval_seconds, args.seed = replay["envs"], replay["seconds"], replay["seed"]
    args.reward_threshold, args.agent = record.get("reward_threshold"), record.get("agent")
    args.overrides = list(record.get("env_overrides", []))
    name, checkpoint = unpack_policy(os.path.join(shipped, POLICY_FILE))
    # a run folder as the training left it: its params and the checkpoint in its library's place
    run_dir = os.path.join(log_root, "restored", task.split("/")[-1])
    shutil.rmtree(run_dir, ignore_errors=True)
    shutil.copytree(os.path.join(shipped, "params"), os.path.join(run_dir, "params"))
    path = os.path.join(run_dir, name)
    os.makedirs(os.path.dirname(path), exist_ok=True)
    write_checkpoint(checkpoint, path, args.library)
    _, cpu, matrices = stage_and_replay(task, path, max(0, record.get("iterations", 1) - 1), args, log_root)
    if not cpu["passed"]:
        return f"no stored form replays to its criterion on the CPU ({matrices}: {cpu['score']:.3f})"
    before = os.path.getsize(os.path.join(shipped, POLICY_FILE))
    staged = os.path.join(log_root, "stored", task.split("/")[-1], args.library, POLICY_FILE)  # stage()'s
    shutil.copyfile(staged, os.path.join(shipped, POLICY_FILE))
    after = os.path.getsize(os.path.join(shipped, POLICY_FILE))
    note = (
        f"stored again on {datetime.date.today().isoformat()} from its shipped {record.get('weights')} weights"
        f" (`{shlex.join(['python', 'scripts/make_pretrained.py', *argv])}`): {matrices}, {before:,} -> {after:,}"
        f" bytes; cpu_evaluation replays this file (before: {replay['score']:.4g})"
    )
    record["weights_note"] = note + (f"; earlier: {record['weights_note']}" if "weights_note" in record else "")
    record.update(weights=matrices, cpu_evaluation=cpu)
    record.setdefault("files_bytes", {})[POLICY_FILE] = after
    with open(record_path, "w") as f:
        json.dump(record, f, indent=2)
        f.write("\n")
    print(f"[make_pretrained] {task}: stored again as {matrices}, {before:,} -> {after:,} bytes", flush=True)
    return None


def task_table() -> list[dict[str, Any]]:
    """Every registered task but the -Play variants: its criterion (or why none), whether it has an
    rsl_rl config (what this script trains with) and which libraries' policies are shipped."""
    import gymnasium as gym

    import simlab.tasks  # noqa: F401 - registers the tasks
    from simlab.pretrained import list_pretrained
    from simlab.tasks.utils.criteria import criterion_for

    shipped = list_pretrained()
    rows = []
    for task in sorted(t for t in gym.registry if t.startswith("simlab/") and "-Play-" not in t):
        try:
            criterion = criterion_for(task).description
        except ValueError as e:
            criterion = f"none: {e}"
        rows.append(
            {
                "task": task,
                "criterion": criterion,
                "rsl_rl": "rsl_rl_cfg_entry_point" in gym.spec(task).kwargs,
                "shipped": [lib for t, lib in shipped if t == task],
            }
        )
    return rows


def check_trainable(
    tasks: list[str], reward_threshold: float | None, library: str = LIBRARY, agent: str | None = None
) -> None:
    """Before hours of training start: every task exists, has a criterion and a config for ``library``
    (the ``agent`` entry point when one is given)."""
    import gymnasium as gym

    from simlab.tasks.utils.criteria import criterion_for

    for task in tasks:
        if task not in gym.registry:
            raise ValueError(f"Unknown task {task}; see python scripts/make_pretrained.py --list")
        criterion_for(task, reward_threshold)
        keys = gym.spec(task).kwargs
        if agent is not None and agent not in keys:
            raise ValueError(
                f"{task} has no agent config {agent}; its configs: {sorted(k for k in keys if 'cfg' in k)}."
            )
        if not any(k.startswith(f"{library}_") and k.endswith("cfg_entry_point") for k in keys):
            raise ValueError(f"{task} has no {library} config ({library}_cfg_entry_point) to play a {library} policy.")


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    args = parse_args(argv)
    if args.list:
        for row in task_table():
            trains = "rsl_rl" if row["rsl_rl"] else "no rsl_rl config"
            shipped = ", ".join(row["shipped"]) or "-"
            print(f"{row['task']}\t{trains}\tshipped: {shipped}\t{row['criterion']}")
        return 0
    import simlab.tasks  # noqa: F401 - registers the tasks
    from simlab.utils.errors import SimlabError

    check_trainable(args.tasks, args.reward_threshold, args.library, args.agent)
    skipped: dict[str, str | None] = {}
    with tempfile.TemporaryDirectory() as scratch:
        log_root = os.path.abspath(args.log_root or scratch)
        os.makedirs(log_root, exist_ok=True)
        for task in args.tasks:
            try:
                make = restore if args.restore else adopt_checkpoint if args.checkpoint else make_one
                skipped[task] = make(task, args, log_root, argv)
            except (OverBudget, RuntimeError, subprocess.SubprocessError, OSError, SimlabError) as e:
                skipped[task] = str(e)
            if skipped[task] is not None:
                print(f"[make_pretrained] SKIPPED {task}: {skipped[task]}; nothing shipped", flush=True)
    print("[make_pretrained] " + "; ".join(f"{t}: {'NOT shipped' if why else 'shipped'}" for t, why in skipped.items()))
    return 0 if not any(skipped.values()) else 1


if __name__ == "__main__":
    sys.exit(main())
