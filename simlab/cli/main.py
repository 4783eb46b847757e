"""The ``simlab`` command (also ``python -m simlab``).

    simlab train --task simlab/Cartpole-v0 --headless [--library rsl_rl|skrl|sb3|rl_games] [overrides]
    simlab play  --task simlab/Cartpole-v0 --use_last_checkpoint [--video] [--eval]
    simlab list  [--keyword cart]
    simlab random|zero --task simlab/Cartpole-v0
    simlab bench ...

Overrides are Hydra-style ``env.<path>=value`` / ``agent.<path>=value`` words after the flags,
e.g. ``env.actions.joint_effort.scale=10 agent.seed=2024``; ``null`` removes a term.
"""

from __future__ import annotations

import argparse
import sys

from simlab.cli.session import LIBRARIES, SKRL_ALGORITHMS
from simlab.utils.gl_backend import GLBackendError
from simlab.viewer import VIEWER_KINDS

__all__ = ["build_parser", "main"]


def _add_common(p: argparse.ArgumentParser, video: bool = True) -> None:
    p.add_argument("--task", required=True, help="Task id, e.g. simlab/Cartpole-v0 (see `simlab list`).")
    p.add_argument("--num_envs", type=int, default=None, help="Number of parallel envs (default: the task's).")
    p.add_argument(
        "--device",
        default=None,
        help="cpu, cuda or cuda:N (default: $SIMLAB_DEVICE, else the GPU if there is one, else cpu).",
    )
    p.add_argument("--seed", type=int, default=None, help="Seed (-1 draws one; default: the agent config's).")
    p.add_argument("--headless", action="store_true", help="No live viewer (same as --viewer none).")
    p.add_argument(
        "--viewer",
        type=str.lower,
        choices=VIEWER_KINDS,
        default="auto",
        help="Live viewer: native (MuJoCo's window), web (in a browser), none; auto: native with a display, else web.",
    )
    p.add_argument("--viewer_port", type=int, default=8080, help="Port of the web viewer (default: 8080).")
    if video:
        p.add_argument("--video", action="store_true", help="Record MP4 videos (rgb_array rendering).")
        p.add_argument("--video_length", type=int, default=200, help="Steps per recorded video.")
        p.add_argument("--video_interval", type=int, default=2000, help="Env steps between recordings.")
    p.add_argument("--log_root", default="logs", help="Root folder of the runs (default: ./logs).")


def _add_agent(p: argparse.ArgumentParser) -> None:
    p.add_argument("--library", choices=LIBRARIES, default="rsl_rl", help="RL library (default: rsl_rl).")
    p.add_argument(
        "--algorithm",
        type=str.upper,
        choices=SKRL_ALGORITHMS,
        default=None,
        help="skrl algorithm: PPO (default), IPPO or MAPPO (multi-agent tasks).",
    )
    p.add_argument("--checkpoint", default=None, help="Checkpoint file (or run folder) to resume from / play.")
    p.add_argument("--distributed", action="store_true", help="Multi-GPU training (not yet supported).")
    p.add_argument("--verbose", action="store_true", help="Print the libraries' own per-iteration logs.")


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="simlab",
        description="Train, play and list simlab tasks.",
        formatter_class=argparse.RawDescriptionHelpFormatter,
        epilog=__doc__.split("\n\n", 1)[1],
    )
    sub = parser.add_subparsers(dest="command", metavar="{train,play,list,random,zero,bench}")
    sub.required = True

    p = sub.add_parser("train", help="Train a policy.")
    _add_common(p)
    _add_agent(p)
    p.add_argument("--max_iterations", type=int, default=None, help="Training iterations (default: the agent's).")
    p.add_argument("--run_name", default="", help="Suffix of the run folder: <timestamp>_<run_name>.")

    p = sub.add_parser("play", help="Run a trained policy; export it to ONNX and TorchScript.")
    _add_common(p)
    _add_agent(p)
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
    p.add_argument("--eval", action="store_true", help="Report episode returns and lengths at the end.")
    p.add_argument("--no_export", action="store_true", help="Do not export the policy.")

    p = sub.add_parser("list", help="List the registered tasks.")
    p.add_argument("--keyword", default=None, help="Only tasks whose id contains this word.")

    for name, text in (("random", "random actions"), ("zero", "zero actions")):
        p = sub.add_parser(name, help=f"Step a task with {text} (a quick check that it runs).")
        _add_common(p, video=False)
        p.add_argument("--steps", type=int, default=None, help="Env steps to run (default: until Ctrl+C).")

    sub.add_parser("bench", help="Benchmarks (simlab bench --help).", add_help=False)
    return parser


def main(argv: list[str] | None = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    if argv and argv[0] == "bench":
        from simlab.benchmarks.cli import main as bench_main

        return int(bench_main(argv[1:]) or 0)
    parser = build_parser()
    args, rest = parser.parse_known_args(argv)
    bad = [a for a in rest if "=" not in a or a.startswith("-")]
    if bad:
        parser.error(f"unrecognized arguments: {' '.join(bad)} (overrides look like env.x.y=1 or agent.z=2)")
    try:
        if args.command == "list":
            from simlab.cli.list_tasks import list_tasks

            return list_tasks(args.keyword)
        if args.command in ("random", "zero"):
            if rest:
                parser.error("random/zero take no overrides")
            from simlab.cli.random_agent import run_random

            return run_random(args, zero=args.command == "zero")
        if args.command == "train":
            from simlab.cli.train import run_train

            run_train(args, rest, argv=["simlab", *argv])
            return 0
        if args.command == "play":
            from simlab.cli.play import run_play

            run_play(args, rest)
            return 0
    except KeyboardInterrupt:
        return 130
    except (ValueError, KeyError, FileNotFoundError, ImportError, NotImplementedError, GLBackendError) as e:
        print(f"simlab {args.command}: error: {e}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
