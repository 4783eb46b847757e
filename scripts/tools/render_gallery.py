"""Render one picture of every registered task for the documentation's task gallery.

    MUJOCO_GL=osmesa python scripts/tools/render_gallery.py --out build/gallery
    python scripts/tools/render_gallery.py --out build/gallery --tasks Cartpole Go2   # ids containing a word

Each task is built with a few envs on the CPU, reset, stepped with zero actions for a moment so that
robots settle, and rendered by simlab's offscreen renderer (``env.render()``, the one ``--video``
uses) into ``<out>/<task id with '/' as '__'>.png``. The pictures are build outputs: ``mkdocs build``
(docs/hooks.py) puts them on the gallery page, and git ignores ``build/``.
"""

from __future__ import annotations

import argparse
import os
import sys
import time

# render with software OpenGL unless told otherwise: the docs are built on machines without a GPU
os.environ.setdefault("MUJOCO_GL", "osmesa")


def picture_name(task: str) -> str:
    """The file name of a task's picture: ``simlab/Cartpole-v0`` -> ``simlab__Cartpole-v0.png``."""
    return task.replace("/", "__") + ".png"


def render_task(task: str, path: str, width: int, height: int, num_envs: int, settle_s: float) -> None:
    """Build ``task`` on the CPU, settle it under zero actions for ``settle_s`` seconds of sim time,
    and write env 0's view (the task's ``cfg.viewer`` camera) to ``path`` as a PNG."""
    import gymnasium as gym
    import imageio.v3 as iio
    import torch

    from simlab.tasks.utils import parse_env_cfg

    cfg = parse_env_cfg(task, device="cpu", num_envs=num_envs)
    cfg.viewer.resolution = (width, height)
    env = gym.make(task, cfg=cfg, render_mode="rgb_array")
    try:
        env.reset(seed=0)
        base = env.unwrapped
        steps = max(1, round(settle_s / base.step_dt))
        actions = _zero_actions(base)
        with torch.inference_mode():
            for _ in range(steps):
                env.step(actions)
        image = base.render()
    finally:
        env.close()
    tmp = path + ".tmp.png"
    iio.imwrite(tmp, image)
    os.replace(tmp, path)


def _zero_actions(env):
    """Zero actions as the env takes them (Isaac Lab's layout: a Discrete action is one column), or
    one per agent for a multi-agent env."""
    import torch

    from simlab.envs.utils.spaces import sample_space

    if hasattr(env, "possible_agents"):  # DirectMARLEnv
        return {a: torch.zeros(env.num_envs, env.cfg.action_spaces[a], device=env.device) for a in env.possible_agents}
    return sample_space(env.single_action_space, env.device, env.num_envs, fill_value=0)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", required=True, help="folder for the PNGs (created)")
    parser.add_argument("--tasks", nargs="*", default=None, help="only task ids containing one of these words")
    parser.add_argument("--width", type=int, default=320)
    parser.add_argument("--height", type=int, default=240)
    parser.add_argument("--num_envs", type=int, default=4, help="envs per task: neighbours show in the picture")
    parser.add_argument("--settle_s", type=float, default=0.2, help="sim seconds of zero actions before the picture")
    args = parser.parse_args(argv)
    if args.width < 16 or args.height < 16:
        parser.error(f"--width and --height must be at least 16 pixels, got {args.width}x{args.height}")
    if args.num_envs < 1:
        parser.error(f"--num_envs must be at least 1, got {args.num_envs}")

    from simlab.tasks.utils import registered_task_ids
    from simlab.utils.errors import ConfigError

    tasks = registered_task_ids()
    if args.tasks:
        tasks = [t for t in tasks if any(w.lower() in t.lower() for w in args.tasks)]
        if not tasks:
            parser.error(f"no registered task id contains any of {args.tasks} (see `simlab list`)")
    os.makedirs(args.out, exist_ok=True)
    failed = []
    for task in tasks:
        start = time.perf_counter()
        path = os.path.join(args.out, picture_name(task))
        try:
            try:
                render_task(task, path, args.width, args.height, args.num_envs, args.settle_s)
            except ConfigError as e:
                if "-Play" not in task:
                    raise
                # a Play variant that needs a file only training writes (the vision hand's CNN):
                # its scene is its training variant's, pictured instead
                print(f"[gallery] {task}: {e}; picturing {task.replace('-Play', '')} instead", flush=True)
                render_task(task.replace("-Play", ""), path, args.width, args.height, args.num_envs, args.settle_s)
        except Exception as e:  # one task that cannot render must not hide the others' pictures
            failed.append(task)
            print(f"[gallery] {task}: FAILED: {type(e).__name__}: {e}", file=sys.stderr, flush=True)
            continue
        print(f"[gallery] {task}: {path} ({time.perf_counter() - start:.1f} s)", flush=True)
    if failed:
        print(f"[gallery] {len(failed)} of {len(tasks)} tasks did not render: {failed}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
