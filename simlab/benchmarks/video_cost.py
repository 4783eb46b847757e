"""What recording a video costs an env's steps: none, gymnasium's ``RecordVideo``, and simlab's.

    simlab bench video --task simlab/Cartpole-v0 --device cpu --steps 100 --repeats 2

One env (the task's env count unless ``--num_envs``), stepped ``--steps`` times with zero actions
three ways, in alternating rounds: without a video; recording with gymnasium's ``RecordVideo``,
which draws every step; and with simlab's (what ``--video`` uses), which draws at most 30 frames per
simulated second. Both recordings use simlab's offscreen renderer and write their clip. The figures
are the best seconds per round, each against the run without a video, and the frames drawn.
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time

KINDS = ("no video", "gymnasium RecordVideo", "simlab --video")


def _round(env, kind: str, steps: int, folder: str) -> tuple[float, int]:
    """Seconds for ``steps`` steps of ``env`` recorded as ``kind``, and the frames drawn."""
    import gymnasium as gym
    import torch

    from simlab.cli.session import _RecordVideo

    drawn = [0]
    base = env.unwrapped
    render = type(base).render
    base.render = lambda: drawn.__setitem__(0, drawn[0] + 1) or render(base)
    wrapped = env
    if kind != "no video":
        wrapper = gym.wrappers.RecordVideo if kind.startswith("gymnasium") else _RecordVideo
        folder = os.path.join(tempfile.mkdtemp(dir=folder), "clips")  # gymnasium warns about an existing one
        wrapped = wrapper(env, video_folder=folder, step_trigger=lambda step: step == 0, video_length=steps)
    actions = torch.zeros(base.num_envs, gym.spaces.flatdim(base.single_action_space), device=base.device)
    wrapped.reset()
    start = time.perf_counter()
    for _ in range(steps):
        wrapped.step(actions)
    if getattr(wrapped, "recording", False):
        wrapped.stop_recording()  # the clip is written: part of what a recording costs
    took = time.perf_counter() - start
    del base.render
    return took, drawn[0]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog="simlab bench video", description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("--task", default="simlab/Cartpole-v0")
    parser.add_argument("--device", default="cpu")
    parser.add_argument("--num_envs", type=int, default=None, help="Default: the task's.")
    parser.add_argument("--steps", type=int, default=100)
    parser.add_argument("--repeats", type=int, default=2)
    args = parser.parse_args(argv)

    import gymnasium as gym

    from simlab.cli.session import load_configs

    cfg, _ = load_configs(args, [], with_agent=False)  # the env count and device as simlab play takes them
    cfg.seed = 0
    env = gym.make(args.task, cfg=cfg, render_mode="rgb_array")
    times: dict[str, list[float]] = {kind: [] for kind in KINDS}
    frames: dict[str, int] = {}
    try:
        with tempfile.TemporaryDirectory(prefix="simlab-bench-video-") as folder:
            _round(env, "simlab --video", 2, folder)  # the renderer's start-up, outside the figures
            for _ in range(args.repeats):
                for kind in KINDS:  # interleaved: a machine's slow minute hits every kind alike
                    took, frames[kind] = _round(env, kind, args.steps, folder)
                    times[kind].append(took)
    finally:
        env.close()
    base = min(times["no video"])
    print(f"{args.task}, {env.unwrapped.num_envs} envs on {cfg.sim.device}, {args.steps} steps:")
    print("| run | seconds | vs no video | frames drawn |")
    print("| --- | --- | --- | --- |")
    for kind in KINDS:
        runs = ", ".join(f"{t:.2f}" for t in times[kind])
        best = min(times[kind])
        print(f"| {kind} | {best:.2f} (runs: {runs}) | {best / base:.1f}x | {frames[kind]} |", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
