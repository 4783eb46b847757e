"""The ``simlab`` command (also ``python -m simlab``).

    simlab train --task simlab/Cartpole-v0 --headless [--library rsl_rl|skrl|sb3|rl_games] [overrides]
    simlab play  --task simlab/Cartpole-v0 --use_last_checkpoint [--video] [--eval]
    simlab list  [cart]
    simlab random|zero --task simlab/Cartpole-v0
    simlab record --task simlab/Cartpole-v0 --dataset_file demos.hdf5 --num_demos 5
    simlab replay --task simlab/Cartpole-v0 --dataset_file demos.hdf5 --validate_states
    simlab bench ...

Overrides are Hydra-style ``env.<path>=value`` / ``agent.<path>=value`` words after the flags,
e.g. ``env.actions.joint_effort.scale=10 agent.seed=2024``; ``null`` removes a term.

A wrong input (flag, override, device, checkpoint) prints one line and exits with 2 (``--debug``
adds the traceback); an unexpected error shows its traceback and exits with 1. Ctrl+C and SIGTERM
stop training after saving a checkpoint (exit 130 / 143).
"""

from __future__ import annotations

import argparse
import contextlib
import gc
import os
import signal
import sys
import threading
import traceback
from collections.abc import Callable, Iterator
from typing import Any

from simlab.cli.distributed import add_launch_args, end_torchrun_worker
from simlab.cli.session import LIBRARIES, SKRL_ALGORITHMS
from simlab.utils.errors import is_intended_error, is_storage_error
from simlab.utils.startup import pause_collector_for_start_up, resume_collector_after_start_up
from simlab.viewer import DEFAULT_HOST, DEFAULT_PORT, VIEWER_KINDS

__all__ = ["allowed_modules", "build_parser", "main"]


def _add_debug(p: argparse.ArgumentParser) -> None:
    p.add_argument("--debug", action="store_true", help="Show the full traceback of every error.")


def _add_common(p: argparse.ArgumentParser, video: bool = True, seed_default: str = "the agent config's") -> None:
    _add_debug(p)
    p.add_argument("--task", required=True, help="Task id, e.g. simlab/Cartpole-v0 (see `simlab list`).")
    p.add_argument("--num_envs", type=int, default=None, help="Number of parallel envs (default: the task's).")
    p.add_argument(
        "--device",
        default=None,
        help="cpu, cuda or cuda:N (default: $SIMLAB_DEVICE, else the GPU if there is one, else cpu).",
    )
    p.add_argument("--seed", type=int, default=None, help=f"Seed (-1 draws one; default: {seed_default}).")
    p.add_argument("--headless", action="store_true", help="No live viewer (same as --viewer none).")
    p.add_argument(
        "--viewer",
        type=str.lower,
        choices=VIEWER_KINDS,
        default="auto",
        help="Live viewer: native (MuJoCo's window), web (in a browser), none; auto: native with a display, else web.",
    )
    p.add_argument(
        "--viz",
        "--visualizer",
        dest="visualizer",
        default=None,
        help="Isaac Lab 3.0's viewer flag: native, web, none, or its names newton_gl (native), viser (web).",
    )
    p.add_argument("--viewer_port", type=int, default=DEFAULT_PORT, help="Port of the web viewer (default: 8080).")
    p.add_argument(
        "--viewer_host",
        default=DEFAULT_HOST,
        help="Address the web viewer listens on (default: 127.0.0.1, this machine only; 0.0.0.0: every network). "
        "Its printed URL carries the token that opens it.",
    )
    p.add_argument(
        "--enable_cameras", action="store_true", help="Accepted as in Isaac Lab: simlab's cameras always render."
    )
    if video:
        p.add_argument("--video", action="store_true", help="Record MP4 videos (rgb_array rendering).")
        p.add_argument("--video_length", type=int, default=200, help="Steps per recorded video.")
        p.add_argument("--video_interval", type=int, default=2000, help="Env steps between recordings.")
    p.add_argument("--log_root", default="logs", help="Root folder of the runs (default: ./logs).")
    p.add_argument(
        "--allow_module",
        action="append",
        default=[],
        metavar="MODULE",
        help="Let 'module:name' values in overrides name MODULE's functions (beside simlab's and the task's "
        "package). Repeatable.",
    )


def _add_agent(
    p: argparse.ArgumentParser, library_default: str | None = "rsl_rl", default_help: str = "rsl_rl"
) -> None:
    p.add_argument(
        "--library",
        "--rl_library",
        choices=LIBRARIES,
        default=library_default,  # None: the command picks (play: the library of the task's shipped policy)
        help=f"RL library (default: {default_help}); --rl_library is Isaac Lab 3.0's name.",
    )
    p.add_argument(
        "--algorithm",
        type=str.upper,
        choices=SKRL_ALGORITHMS,
        default=None,
        help="skrl algorithm: PPO (default), AMP (AMP tasks), IPPO or MAPPO (multi-agent tasks).",
    )
    p.add_argument("--checkpoint", default=None, help="Checkpoint file (or run folder) to resume from / play.")
    p.add_argument(
        "--force",
        action="store_true",
        help="Use a checkpoint even if it was trained with another library, task or observation/action size.",
    )
    p.add_argument(
        "--trust_checkpoint",
        action="store_true",
        help="Load a checkpoint that holds more than weights (pickled objects can run code): only for files you trust.",
    )
    p.add_argument(
        "--agent",
        default=None,
        help="Registry key of the agent config (default: <library>_cfg_entry_point, or skrl's for --algorithm).",
    )
    p.add_argument("--verbose", action="store_true", help="Print the libraries' own per-iteration logs.")


OVERRIDES_HELP = (
    "After the flags, Hydra-style overrides of any config field: env.<path>=value, agent.<path>=value "
    "(e.g. env.scene.num_envs=64 agent.seed=2024; null removes a term)."
)


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="simlab",
        description="Train, play and list simlab tasks.",
        formatter_class=argparse.RawDescriptionHelpFormatter,
        epilog=__doc__.split("\n\n", 1)[1],
    )
    sub = parser.add_subparsers(dest="command", metavar="{train,play,list,random,zero,record,replay,bench}")
    sub.required = True

    p = sub.add_parser("train", help="Train a policy.", epilog=OVERRIDES_HELP)
    _add_common(p)
    _add_agent(p)
    p.add_argument("--max_iterations", type=int, default=None, help="Training iterations (default: the agent's).")
    p.add_argument("--run_name", default="", help="Suffix of the run folder: <timestamp>_<run_name>.")
    p.add_argument(
        "--init_weights",
        default=None,
        metavar="CHECKPOINT",
        help="Start a new run (iteration 0, a fresh optimizer) from this checkpoint's network weights: its actor, "
        "and its critic where it has one. It may come from another task with the same observation and action "
        "sizes (fine-tuning); --checkpoint resumes a run of this task instead. rsl_rl.",
    )
    p.add_argument(
        "--warmup_critic",
        type=int,
        default=0,
        metavar="N",
        help="With --init_weights: the first N iterations train the critic only (the actor's weights are put "
        "back after each update), so an untrained critic does not steer the policy it was given.",
    )
    p.add_argument(
        "--export_io_descriptors",
        action="store_true",
        help="Write the policy's observation and action terms to <run>/io_descriptors/IO_descriptors.yaml "
        "(manager-based tasks).",
    )
    p.add_argument(
        "--distributed",
        action="store_true",
        help="Train on several GPUs or nodes (torch.distributed; gloo on the CPU). Under torchrun each "
        "process trains; without torchrun simlab launches it, one process per GPU (see the launch flags).",
    )
    p.add_argument(
        "--ml_framework",
        choices=("torch", "jax", "jax-numpy"),
        default="torch",
        help="skrl's backend: torch (default), jax or jax-numpy (needs simlab[jax]).",
    )
    add_launch_args(p)

    p = sub.add_parser("play", help="Run a trained policy; export it to ONNX and TorchScript.", epilog=OVERRIDES_HELP)
    _add_common(p)
    _add_agent(p, None, "rsl_rl; with --use_pretrained_checkpoint, that of the task's only shipped policy")
    p.add_argument(
        "--use_last_checkpoint",
        action="store_true",
        help="Play the newest checkpoint of the newest run of this task and library.",
    )
    p.add_argument(
        "--steps",
        type=int,
        default=None,
        help="Env steps to run (default: one episode with --eval or --video, else until Ctrl+C).",
    )
    p.add_argument(
        "--seconds",
        type=float,
        default=None,
        help="Simulated seconds to run instead of --steps (env steps of the task's sim.dt * decimation).",
    )
    p.add_argument(
        "--use_pretrained_checkpoint",
        action="store_true",
        help="Play the policy shipped with simlab for this task and library (copied to <log_root>/pretrained/).",
    )
    p.add_argument("--eval", action="store_true", help="Report episode returns and lengths at the end.")
    p.add_argument("--no_export", action="store_true", help="Do not export the policy.")
    p.add_argument("--real-time", action="store_true", help="Step no faster than simulated time (for watching).")

    p = sub.add_parser("list", help="List the registered tasks.")
    p.add_argument("keyword", nargs="?", default=None, help="Only tasks whose id contains this word (any case).")
    p.add_argument("--keyword", dest="keyword_flag", default=None, help="The same (Isaac Lab's list_envs.py flag).")
    _add_debug(p)

    for name, text in (("random", "random actions"), ("zero", "zero actions")):
        p = sub.add_parser(name, help=f"Step a task with {text} (a quick check that it runs).")
        _add_common(p, video=False, seed_default="0")
        p.add_argument("--steps", type=int, default=None, help="Env steps to run, then stop (default: until Ctrl+C).")
        p.add_argument(
            "--save_camera_frames",
            metavar="DIR",
            default=None,
            help="Write each camera's images of up to 16 envs as one tiled PNG to DIR, after the reset and at the end.",
        )

    p = sub.add_parser("record", help="Record scripted episodes of a manager-based task into an HDF5 dataset.")
    _add_common(p, video=False)
    p.add_argument("--dataset_file", default="./datasets/dataset.hdf5", help="HDF5 file to write.")
    p.add_argument("--num_demos", type=int, default=1, help="Finished episodes to record (default: 1).")
    p.add_argument("--actions", choices=("random", "zero"), default="random", help="Seeded random or zero actions.")
    p.add_argument("--overwrite", action="store_true", help="Replace an existing --dataset_file.")

    p = sub.add_parser("replay", help="Replay the episodes of an HDF5 dataset (and check the states).")
    _add_common(p, video=False)
    p.add_argument("--dataset_file", required=True, help="HDF5 file written by simlab record.")
    p.add_argument("--select_episodes", type=int, nargs="+", default=None, help="Episode indices (default: all).")
    p.add_argument("--validate_states", action="store_true", help="Compare each state with the recorded one.")

    sub.add_parser("bench", help="Benchmarks (simlab bench --help).", add_help=False)
    return parser


class Terminated(KeyboardInterrupt):
    """SIGTERM (what a cluster scheduler sends): handled like Ctrl+C, so training saves a checkpoint."""


# exit codes of a process stopped by SIGINT / SIGTERM (128 + signal number), as shells report them
EXIT_INTERRUPTED = 130
EXIT_BROKEN_PIPE = 141  # the reader of the output went away (`simlab list | head`)
EXIT_TERMINATED = 143
EXIT_ERROR = 2  # a wrong input or a state the user can fix; argparse uses 2 for wrong flags too
EXIT_BUG = 1  # an unexpected exception, as Python exits on one


def _raise_terminated(signum: int, frame: Any) -> None:
    raise Terminated


@contextlib.contextmanager
def _sigterm_as_interrupt() -> Iterator[None]:
    """Within the block, SIGTERM raises :class:`Terminated` (a ``KeyboardInterrupt``)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.signal(signal.SIGTERM, _raise_terminated)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, previous)


@contextlib.contextmanager
def _background_storage_errors() -> Iterator[list[BaseException]]:
    """Within the block, a background thread that dies of a full disk or a read-only folder (TensorBoard's
    event writer) prints no traceback: its writer raises the error again in the command's thread, which
    reports it in one line. The errors are collected in the list the block gets."""
    stopped: list[BaseException] = []
    previous = threading.excepthook

    def hook(args: threading.ExceptHookArgs) -> None:
        if args.exc_value is not None and is_storage_error(args.exc_value):
            stopped.append(args.exc_value)
        else:
            previous(args)

    threading.excepthook = hook
    try:
        yield stopped
    finally:
        threading.excepthook = previous


def _report(command: str, error: BaseException, debug: bool) -> int:
    """The CLI's one place for errors: simlab's own as one line (exit 2), anything else with its traceback (1)."""
    if not is_intended_error(error):
        traceback.print_exception(error)
        return EXIT_BUG
    if debug:
        traceback.print_exception(error)
    else:
        text = str(error).strip() or type(error).__name__
        if isinstance(error, KeyError) and len(error.args) == 1:
            text = str(error.args[0])  # KeyError's str() adds quotes
        print(f"simlab {command}: error: {text}", file=sys.stderr)
    return EXIT_ERROR


def main(argv: list[str] | None = None) -> int:
    """The command line's entry point (``argv`` None: ``sys.argv``); returns the exit code."""
    words = list(sys.argv[1:] if argv is None else argv)
    if argv is None and _trains(words):  # this process is the command's own: its start-up may pause the collector
        pause_collector_for_start_up()
    try:
        code = _main(words)
        if argv is None:
            sys.stdout.flush()  # here, where a reader that went away is caught
    except BrokenPipeError:  # stdout's reader closed it (`simlab list | head -1`): stop quietly
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())  # Python's own flush at exit would fail too
        code = EXIT_BROKEN_PIPE
    finally:
        resume_collector_after_start_up()  # training resumes it itself; this is for an error before
    if argv is None:  # the process ends next: not when a caller (a test, a script) goes on
        _skip_collection_at_exit()
        end_torchrun_worker(code)
    return code


def _trains(words: list[str]) -> bool:
    """Whether the command is ``simlab train`` or ``simlab bench solve``: the commands that resume the
    garbage collector when their start-up is done (before the first training iteration)."""
    return bool(words) and (words[0] == "train" or (words[0] == "bench" and "solve" in words[1:]))


def _skip_collection_at_exit() -> None:
    """Leave the objects that exist now out of the garbage collection Python runs as it exits.

    With torch, torch._dynamo and sympy loaded that collection took 0.6-1.5 s of every command
    (2 CPU cores; `gc.freeze()` measured it down to 0.1-0.3 s). The command is done: its
    checkpoints are saved and its writers flushed and closed, so nothing waits on a finalizer.
    """
    sys.stdout.flush()
    sys.stderr.flush()
    gc.freeze()


def _main(argv: list[str]) -> int:
    if argv and argv[0] == "bench":
        from simlab.benchmarks.cli import main as bench_main

        return _run_command("bench", False, lambda: bench_main(argv[1:]))  # `bench solve` trains
    parser = build_parser()
    args, rest = parser.parse_known_args(argv)
    bad = [a for a in rest if "=" not in a or a.startswith("-")]
    if bad:
        parser.error(f"unrecognized arguments: {' '.join(bad)} (overrides look like env.x.y=1 or agent.z=2)")
    return _run_command(args.command, getattr(args, "debug", False), lambda: _dispatch(parser, args, rest, argv))


def _run_command(command: str, debug: bool, run: Callable[[], int | None]) -> int:
    """Run a command with SIGTERM handled as Ctrl+C (a training saves its checkpoint), and errors
    reported by :func:`_report`; the command's exit code."""
    try:
        with _sigterm_as_interrupt(), _background_storage_errors() as stopped:
            code = int(run() or 0)
        for error in stopped:  # the command finished without the writer's output: say so
            print(f"[simlab] WARNING: a background writer stopped: {error}", file=sys.stderr)
        return code
    except Terminated:
        return EXIT_TERMINATED
    except KeyboardInterrupt:
        return EXIT_INTERRUPTED
    except BrokenPipeError:
        raise  # main() ends the command quietly
    except Exception as e:  # noqa: BLE001 - the one place that turns errors into messages
        return _report(command, e, debug)


def allowed_modules(args: argparse.Namespace) -> list[str]:
    """The packages whose functions ``module:name`` values may name: simlab, the task's own package
    (of its registered env and env config) and those given with ``--allow_module``."""
    packages = ["simlab", *getattr(args, "allow_module", [])]
    if getattr(args, "task", None):
        import gymnasium as gym

        import simlab.tasks  # noqa: F401 - registers the tasks
        from simlab.utils.string import simlab_task_id

        try:
            spec = gym.spec(simlab_task_id(args.task))
        except gym.error.Error:
            return packages  # the command names the unknown task itself
        for entry in (spec.entry_point, spec.kwargs.get("env_cfg_entry_point")):
            module = entry if isinstance(entry, str) else getattr(entry, "__module__", None)
            if module:
                packages.append(module.split(":")[0].split(".")[0])
    return packages


def _isaaclab3_words(args: argparse.Namespace, rest: list[str]) -> list[str]:
    """Isaac Lab 3.0's words in simlab's terms (:mod:`simlab.cli.isaaclab3`): the task id (version-less,
    ``Isaac-`` ids), ``--viz``, and the ``physics=`` / ``renderer=`` / ``presets=`` selectors; the
    overrides left."""
    if not getattr(args, "task", None):
        return rest
    import simlab.tasks  # noqa: F401 - registers the tasks (their versions)
    from simlab.cli.isaaclab3 import apply_selectors, apply_visualizer, split_selectors
    from simlab.utils.string import simlab_task_id

    task = simlab_task_id(args.task)
    if task != args.task:
        print(f"[simlab] Task {args.task} -> {task}")
        args.task = task
    apply_visualizer(args)
    if args.command == "play":
        _checkpoint_selector(args)
    if args.command not in ("train", "play", "random", "zero"):
        return rest
    selectors, rest = split_selectors(rest)
    apply_selectors(args, selectors)
    return rest


def _checkpoint_selector(args: argparse.Namespace) -> None:
    """Isaac Lab 3.0's ``play --checkpoint latest`` / ``pretrained`` (where no such file exists)."""
    selector = args.checkpoint
    if selector not in ("latest", "best", "pretrained") or os.path.exists(selector):
        return
    if selector == "best":
        from simlab.utils.errors import ConfigError

        raise ConfigError("--checkpoint best: simlab keeps no best checkpoint; use --checkpoint latest or a path.")
    args.checkpoint = None
    flag = "use_last_checkpoint" if selector == "latest" else "use_pretrained_checkpoint"
    setattr(args, flag, True)
    print(f"[simlab] --checkpoint {selector} -> --{flag}")


def _dispatch(parser: argparse.ArgumentParser, args: argparse.Namespace, rest: list[str], argv: list[str]) -> int:
    from simlab.cli.isaaclab3 import renderer_choice
    from simlab.utils.string import callable_modules

    rest = _isaaclab3_words(args, rest)
    # a "module:name" value (an override, a run's params) names functions of these packages only
    with callable_modules(allowed_modules(args)), renderer_choice(getattr(args, "renderer", None)):
        return _run(parser, args, rest, argv)


def _run(parser: argparse.ArgumentParser, args: argparse.Namespace, rest: list[str], argv: list[str]) -> int:
    if args.command == "list":
        from simlab.cli.list_tasks import list_tasks

        return list_tasks(args.keyword or args.keyword_flag)
    if args.command in ("random", "zero"):
        if rest:
            parser.error("random/zero take no overrides")
        from simlab.cli.random_agent import run_random

        return run_random(args, zero=args.command == "zero")
    if args.command in ("record", "replay"):
        from simlab.cli.demos import run_record, run_replay

        return (run_record if args.command == "record" else run_replay)(args, rest)
    if args.command == "train":
        from simlab.cli.train import launch_distributed, needs_launch, run_train

        if needs_launch(args):
            return launch_distributed(args, argv)
        run_train(args, rest, argv=["simlab", *argv])
    elif args.command == "play":
        from simlab.cli.play import RealTimePacer, run_play

        run_play(args, rest, on_step=RealTimePacer() if args.real_time else None)
    return 0


if __name__ == "__main__":
    sys.exit(main())
