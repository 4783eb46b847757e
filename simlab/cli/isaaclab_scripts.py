"""Isaac Lab's per-library scripts, ``scripts/reinforcement_learning/<library>/{train,play}.py``, on simlab's CLI.

Each script calls :func:`train_main` or :func:`play_main` with its library. They parse Isaac Lab's flags
for that library (plus the AppLauncher flags and Hydra-style overrides), translate them into a
``simlab train`` / ``simlab play`` command line and run it through :func:`simlab.cli.main.main`: the
scripts and ``simlab train`` run the same code. Isaac Lab task ids (``Isaac-Cartpole-v0``) are mapped
to simlab's (``simlab/Cartpole-v0``). Under torchrun, ``train.py ... --distributed`` trains one process
per GPU as ``simlab train --distributed`` does.
"""

from __future__ import annotations

import argparse
import os
import sys

from simlab.app.app_launcher import AppLauncher
from simlab.cli.session import LIBRARIES

__all__ = ["build_script_parser", "play_main", "script_to_simlab_argv", "train_main"]

# flags Isaac Lab's scripts take that change nothing here, and why
_NO_EFFECT = {
    "disable_fabric": "simlab has no USD/Fabric layer",
    "keep_all_info": "simlab's SB3 wrapper keeps the env's info dicts it needs",
    "log_interval": "simlab shows a progress bar and logs every rollout to TensorBoard",
    "sigma": "rl_games' initial action noise is the agent config's (agent.params.config...)",
    "track": "simlab logs to TensorBoard, not Weights & Biases",
    "wandb_project_name": "simlab logs to TensorBoard, not Weights & Biases",
    "wandb_entity": "simlab logs to TensorBoard, not Weights & Biases",
    "wandb_name": "simlab logs to TensorBoard, not Weights & Biases",
}


def build_script_parser(library: str, mode: str) -> argparse.ArgumentParser:
    """Isaac Lab's ``scripts/reinforcement_learning/<library>/<mode>.py`` flags."""
    if library not in LIBRARIES or mode not in ("train", "play"):
        raise ValueError(f"No Isaac Lab script for library '{library}', mode '{mode}'.")
    verb = "Train an RL agent" if mode == "train" else "Play a checkpoint of an RL agent"
    parser = argparse.ArgumentParser(description=f"{verb} with {library} (Isaac Lab's script, on simlab).")
    parser.add_argument("--video", action="store_true", default=False, help="Record videos.")
    parser.add_argument("--video_length", type=int, default=200, help="Length of the recorded video (in steps).")
    if mode == "train":
        parser.add_argument("--video_interval", type=int, default=2000, help="Interval between recordings (steps).")
    else:
        parser.add_argument("--disable_fabric", action="store_true", help="Accepted; no effect in simlab.")
    parser.add_argument("--num_envs", type=int, default=None, help="Number of environments to simulate.")
    parser.add_argument("--task", type=str, default=None, help="Name of the task (Isaac-* ids are mapped).")
    parser.add_argument("--agent", type=str, default=None, help="Name of the RL agent configuration entry point.")
    parser.add_argument("--seed", type=int, default=None, help="Seed used for the environment.")
    if mode == "train":
        parser.add_argument("--max_iterations", type=int, default=None, help="RL policy training iterations.")
        parser.add_argument("--export_io_descriptors", action="store_true", help="Export IO descriptors.")
        if library != "sb3":
            parser.add_argument("--distributed", action="store_true", help="Run training with multiple GPUs/nodes.")
    else:
        parser.add_argument("--use_pretrained_checkpoint", action="store_true", help="Use a pre-trained checkpoint.")
        parser.add_argument("--real-time", action="store_true", help="Run in real-time, if possible.")
    if library == "rsl_rl":
        group = parser.add_argument_group("rsl_rl", "Arguments for the RSL-RL agent.")
        group.add_argument("--experiment_name", type=str, default=None, help="Folder of the experiment's runs.")
        group.add_argument("--run_name", type=str, default=None, help="Suffix of the run folder.")
        group.add_argument("--resume", action="store_true", default=False, help="Resume from a checkpoint.")
        group.add_argument("--load_run", type=str, default=None, help="Run folder to resume from (regex).")
        group.add_argument("--checkpoint", type=str, default=None, help="Checkpoint file to resume from (or regex).")
        group.add_argument("--logger", type=str, default=None, choices={"wandb", "tensorboard", "neptune"})
        group.add_argument("--log_project_name", type=str, default=None, help="W&B / Neptune project name.")
    else:
        parser.add_argument("--checkpoint", type=str, default=None, help="Path to a model checkpoint.")
    # simlab's trust flags (files from elsewhere are data): see docs/runs.md
    parser.add_argument(
        "--trust_checkpoint", action="store_true", help="Load a checkpoint that holds more than weights."
    )
    parser.add_argument("--allow_module", action="append", default=[], help="Let overrides name MODULE's functions.")
    if library == "skrl":
        parser.add_argument("--ml_framework", type=str, default="torch", choices=["torch", "jax", "jax-numpy"])
        parser.add_argument("--algorithm", type=str, default="PPO", choices=["AMP", "PPO", "IPPO", "MAPPO"])
    if library == "sb3":
        parser.add_argument("--keep_all_info", action="store_true", default=False, help="Keep all env info.")
        if mode == "train":
            parser.add_argument("--log_interval", type=int, default=100_000, help="Log data every n timesteps.")
    if library == "rl_games" and mode == "train":
        parser.add_argument("--sigma", type=str, default=None, help="The policy's initial standard deviation.")
        parser.add_argument("--track", action="store_true", default=False, help="Track with Weights and Biases.")
        parser.add_argument("--wandb-project-name", type=str, default=None, help="W&B project name.")
        parser.add_argument("--wandb-entity", type=str, default=None, help="W&B entity.")
        parser.add_argument("--wandb-name", type=str, default=None, help="W&B run name.")
    if mode == "play" and library in ("sb3", "rl_games"):
        parser.add_argument("--use_last_checkpoint", action="store_true", help="Play the last saved checkpoint.")
    AppLauncher.add_app_launcher_args(parser)
    return parser


def _simlab_task(task: str | None) -> str:
    """Isaac Lab's ``Isaac-<Name>`` ids as simlab's ``simlab/<Name>`` (other ids unchanged)."""
    if not task:
        raise ValueError("--task is required, e.g. --task simlab/Cartpole-v0 (or Isaac Lab's Isaac-Cartpole-v0).")
    from simlab.tasks.utils.parse_cfg import simlab_task_id

    mapped = simlab_task_id(task)
    if mapped != task:
        print(f"[simlab] Task {task} -> {mapped}")
    return mapped


def _rsl_rl_checkpoint(args: argparse.Namespace, task: str, log_root: str) -> str | None:
    """Isaac Lab's rsl_rl resume/play lookup: ``--load_run`` and ``--checkpoint`` are regexes in the logs."""
    if args.checkpoint and os.path.isfile(args.checkpoint):
        return args.checkpoint
    if not (args.resume or args.load_run or args.checkpoint):
        return None
    from simlab.tasks.utils import get_checkpoint_path, load_cfg_from_registry

    experiment = args.experiment_name
    if not experiment:
        experiment = load_cfg_from_registry(task, args.agent or "rsl_rl_cfg_entry_point").experiment_name
    log_path = os.path.join(log_root, "rsl_rl", experiment)
    return get_checkpoint_path(log_path, args.load_run or ".*", args.checkpoint or r"model_.*\.pt")


def script_to_simlab_argv(library: str, mode: str, args: argparse.Namespace, overrides: list[str]) -> list[str]:
    """The ``simlab`` command line that does what the Isaac Lab script was asked to."""
    task = _simlab_task(args.task)
    log_root = "logs"  # Isaac Lab's scripts log to ./logs/<library>/<experiment>, as simlab does
    argv = [mode, "--task", task, "--library", library, "--log_root", log_root]
    for name in ("num_envs", "seed", "device", "agent", "video_length", "viewer", "viewer_port", "viewer_host"):
        value = getattr(args, name, None)
        if value is not None:
            argv += [f"--{name}", str(value)]
    for name in ("headless", "video", "verbose", "trust_checkpoint"):
        if getattr(args, name, False):
            argv.append(f"--{name}")
    for module in getattr(args, "allow_module", []):
        argv += ["--allow_module", module]
    if library == "skrl":
        algorithm = args.algorithm.upper()
        argv += ["--algorithm", algorithm]
        if mode == "train":
            argv += ["--ml_framework", args.ml_framework]
        elif args.ml_framework != "torch":
            raise ValueError("Playing a JAX-trained skrl agent is not supported; play agents trained on torch.")
    for name, why in _NO_EFFECT.items():
        if getattr(args, name, None):
            print(f"[simlab] --{name.replace('_', '-') if name.startswith('wandb') else name} has no effect: {why}.")

    if library == "rsl_rl":
        checkpoint = _rsl_rl_checkpoint(args, task, log_root)
        if args.experiment_name:
            overrides = [*overrides, f"agent.experiment_name={args.experiment_name}"]
        if args.logger:  # rsl_rl's own writers: tensorboard, wandb or neptune
            overrides = [*overrides, f"agent.logger={args.logger}"]
        if args.log_project_name:
            name = args.log_project_name
            overrides = [*overrides, f"agent.wandb_project={name}", f"agent.neptune_project={name}"]
        if args.run_name and mode == "train":
            argv += ["--run_name", args.run_name]
    else:
        checkpoint = args.checkpoint
    if checkpoint:
        argv += ["--checkpoint", checkpoint]

    if mode == "train":
        argv += ["--video_interval", str(args.video_interval)]
        if args.max_iterations is not None:
            argv += ["--max_iterations", str(args.max_iterations)]
        if getattr(args, "distributed", False):
            argv.append("--distributed")
        if args.export_io_descriptors:
            argv.append("--export_io_descriptors")
    else:
        if args.use_pretrained_checkpoint:
            argv.append("--use_pretrained_checkpoint")
        elif not checkpoint:  # Isaac Lab's play scripts default to the newest checkpoint of the newest run
            argv.append("--use_last_checkpoint")
        if args.max_app_steps is not None:  # the app loop's bound: as many env steps
            argv += ["--steps", str(args.max_app_steps)]
        if args.real_time:
            argv.append("--real-time")
    return [*argv, *overrides]


def _main(library: str, mode: str, argv: list[str] | None) -> int:
    from simlab.cli.distributed import end_torchrun_worker
    from simlab.cli.main import main

    parser = build_script_parser(library, mode)
    args, overrides = parser.parse_known_args(sys.argv[1:] if argv is None else argv)
    bad = [a for a in overrides if "=" not in a or a.startswith("-")]
    if bad:
        parser.error(f"unrecognized arguments: {' '.join(bad)} (overrides look like env.x.y=1 or agent.z=2)")
    try:
        simlab_argv = script_to_simlab_argv(library, mode, args, overrides)
    except (ValueError, FileNotFoundError) as e:
        print(f"{mode}.py: error: {e}", file=sys.stderr)
        return 2
    code = main(simlab_argv)
    if argv is None:  # the script is this process: end a torchrun worker as `simlab` ends it
        end_torchrun_worker(code)
    return code


def train_main(library: str, argv: list[str] | None = None) -> int:
    """``scripts/reinforcement_learning/<library>/train.py``."""
    return _main(library, "train", argv)


def play_main(library: str, argv: list[str] | None = None) -> int:
    """``scripts/reinforcement_learning/<library>/play.py``."""
    return _main(library, "play", argv)
