"""Does skrl's AMP learn the humanoid's reference motion? Train, then play the policy and compare with the clip.

    python scripts/benchmarks/amp_learn.py                                   # walk, the task's defaults
    python scripts/benchmarks/amp_learn.py --motion run --max_iterations 2000 --video
    python scripts/benchmarks/amp_learn.py --device cuda:0 --num_envs 4096 --max_iterations 700 \\
        --train_seconds 390 --video                                          # the GPU evidence run
    python scripts/benchmarks/amp_learn.py --motion run --device cuda:0 --num_envs 4096 --max_iterations 5000 \\
        --train_seconds 330 --checkpoint <run>/checkpoints/agent_21584.pt   # resume a run (weights, optimizer)
    python scripts/benchmarks/amp_learn.py --num_envs 4 --max_iterations 3 --device cpu \\
        agent.motion_dataset.memory_size=2048 agent.reply_buffer.memory_size=2048   # a CPU smoke run

Training runs as ``simlab train --task simlab/Humanoid-AMP-<Motion>-Direct-v0 --library skrl
--algorithm AMP --headless`` in a child process (extra arguments, Hydra overrides or ``--checkpoint``,
are passed on to it).
``--train_seconds`` stops it early with SIGTERM (training saves a checkpoint then), so a
run fits a wall-clock budget whatever the device's speed. Reported:

* the discriminator (style) reward of the rollouts, from the run's TensorBoard log
  (``Reward / Style reward (mean)``, one point per write interval): its first and last fifths and
  every tenth point;
  it rises as the policy's transitions become harder to tell from the clip's;
* the mean episode length, from the same log (falls end episodes early);
* from a played policy (its mean actions; ``--eval_envs`` envs, ``--eval_seconds``), counting only
  steps at least ``--settle_seconds`` into an episode: the joint-angle RMS error to the clip's
  nearest frame (AMP imitates a style, not a clock, so each played pose is compared with the clip
  pose closest to it; the same number for the standing zero pose is given for scale), the forward
  speed (world x, the clip's direction) and the horizontal speed beside the clip's, and the falls
  per env-minute;
* with ``--video``: the play video and a PNG of six of its frames (``<video>.frames.png``) to look at.
"""

from __future__ import annotations

import argparse
import glob
import json
import os
import signal
import subprocess
import sys
import time

from simlab.cli.libraries.skrl import STYLE_REWARD_TAG
from simlab.cli.main import build_parser
from simlab.cli.play import run_play
from simlab.rl.utils import require
from simlab.tasks.direct.humanoid_amp.criterion import GaitRecorder
from simlab.tasks.utils import load_cfg_from_registry
from simlab.tasks.utils.hydra import env_overrides_in

MOTIONS = ("walk", "run", "dance")


def train(cmd: list[str], train_seconds: float | None) -> bool:
    """Run the training command; past ``train_seconds`` send it SIGTERM (it saves a checkpoint and stops).
    True when it finished or was stopped by the budget with its checkpoint saved.

    SIGTERM, not SIGINT: a process started from a background shell job inherits SIGINT ignored,
    and Python then never turns it into ``KeyboardInterrupt``; `simlab train` handles SIGTERM itself.
    """
    child = subprocess.Popen(cmd, env={**os.environ, "PYTHONUNBUFFERED": "1"})
    try:
        return child.wait(timeout=train_seconds) == 0
    except subprocess.TimeoutExpired:
        print(f"=== training budget of {train_seconds:g} s spent: stopping it (SIGTERM)", flush=True)
        child.send_signal(signal.SIGTERM)
        return child.wait() in (0, 143)  # 143: simlab's exit status after a SIGTERM that saved


def frame_sheet(video: str, count: int = 6) -> str:
    """A PNG of ``count`` evenly spaced frames of ``video`` side by side (``<video>.frames.png``)."""
    import imageio.v3 as iio
    import numpy as np

    frames = iio.imread(video)
    picks = np.linspace(0, len(frames) - 1, count).round().astype(int)
    path = video + ".frames.png"
    iio.imwrite(path, np.concatenate([frames[i] for i in picks], axis=1))
    return path


def scalars(run_dir: str, tag: str) -> list[float]:
    from tensorboard.backend.event_processing.event_accumulator import EventAccumulator

    events = EventAccumulator(run_dir, size_guidance={"scalars": 0})
    events.Reload()
    return [s.value for s in events.Scalars(tag)] if tag in events.Tags()["scalars"] else []


def trend(values: list[float]) -> dict[str, float | list[float]]:
    """First and last fifth means, the lowest point (AMP's style reward first falls as the discriminator
    learns, then rises as the policy catches up) and up to 10 evenly spaced points."""
    if not values:
        return {}
    fifth = max(1, len(values) // 5)
    step = max(1, len(values) // 10)
    return {
        "first_fifth_mean": sum(values[:fifth]) / fifth,
        "last_fifth_mean": sum(values[-fifth:]) / fifth,
        "min": min(values),
        "min_at_fraction": values.index(min(values)) / max(1, len(values) - 1),
        "last": values[-1],
        "points": [round(v, 4) for v in values[::step]],
        "count": len(values),
    }


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--motion", choices=MOTIONS, default="walk")
    parser.add_argument("--num_envs", type=int, default=None, help="Training envs (default: the task's).")
    parser.add_argument("--max_iterations", type=int, default=None, help="Default: the agent config's.")
    parser.add_argument("--device", default=None)
    parser.add_argument(
        "--train_seconds", type=float, default=None, help="Stop training after this wall time (a saved checkpoint)."
    )
    parser.add_argument("--log_root", default="logs")
    parser.add_argument("--eval_envs", type=int, default=64)
    parser.add_argument("--eval_seconds", type=float, default=10.0)
    parser.add_argument("--settle_seconds", type=float, default=0.5, help="Skip this much of each episode.")
    parser.add_argument("--video", action="store_true", help="Record a play video (in the run's videos/play).")
    parser.add_argument("--skip_training", action="store_true", help="Evaluate the newest amp_learn run only.")
    parser.add_argument("--json", default=None, help="Also write the results to this JSON file.")
    args, overrides = parser.parse_known_args()
    task = f"simlab/Humanoid-AMP-{args.motion.capitalize()}-Direct-v0"
    if args.video:
        require("moviepy")  # play's video writer: fail now, not after the training

    wall = float("nan")
    if not args.skip_training:
        cmd = [sys.executable, "-m", "simlab", "train", "--task", task, "--library", "skrl", "--algorithm", "AMP"]
        cmd += ["--headless", "--log_root", args.log_root, "--run_name", "amp_learn"]
        for flag in ("num_envs", "max_iterations", "device"):
            if getattr(args, flag) is not None:
                cmd += [f"--{flag}", str(getattr(args, flag))]
        cmd += overrides
        print(f"=== {' '.join(cmd[2:])}", flush=True)
        start = time.time()
        if not train(cmd, args.train_seconds):
            return 1
        wall = time.time() - start

    experiment = load_cfg_from_registry(task, "skrl_amp_cfg_entry_point")["agent"]["experiment"]["directory"]
    runs = sorted(glob.glob(os.path.join(args.log_root, "skrl", experiment, "*_amp_learn")))
    if not runs:
        where = os.path.join(args.log_root, "skrl", experiment)
        print(f"No amp_learn run of {task} under {where}; train first (drop --skip_training).")
        return 1
    run_dir = runs[-1]
    checkpoints = glob.glob(os.path.join(run_dir, "checkpoints", "agent_*.pt"))
    checkpoint = max(checkpoints, key=lambda p: int(os.path.basename(p)[len("agent_") : -len(".pt")]))
    rollouts = load_cfg_from_registry(task, "skrl_amp_cfg_entry_point")["agent"]["rollouts"]
    iterations = int(os.path.basename(checkpoint)[len("agent_") : -len(".pt")]) // rollouts

    play_argv = ["play", "--task", task, "--library", "skrl", "--algorithm", "AMP", "--checkpoint", checkpoint]
    play_argv += ["--headless", "--num_envs", str(args.eval_envs), "--seconds", str(args.eval_seconds), "--no_export"]
    play_argv += ["--log_root", args.log_root]
    if args.device:
        play_argv += ["--device", args.device]
    if args.video:
        play_argv += ["--video", "--video_length", "300"]  # cut short by a shorter play
    recorder = GaitRecorder(args.settle_seconds)
    # the trained env's settings
    run_play(build_parser().parse_args(play_argv), env_overrides_in(overrides), on_step=recorder)
    videos = sorted(glob.glob(os.path.join(run_dir, "videos", "play", "*.mp4")), key=os.path.getmtime)
    sheet = frame_sheet(videos[-1]) if args.video and videos else None

    results = {
        "task": task,
        "run_dir": run_dir,
        "checkpoint": checkpoint,
        "train_wall_s": wall,
        "iterations": iterations,
        "video_frames_png": sheet,
        "style_reward": trend(scalars(run_dir, STYLE_REWARD_TAG)),
        "episode_length_steps": trend(scalars(run_dir, "Episode / Total timesteps (mean)")),
        "play": {"envs": args.eval_envs, "seconds": args.eval_seconds, **recorder.summary()},
    }
    style, episodes, play = results["style_reward"], results["episode_length_steps"], results["play"]
    print(f"\n{task}: {run_dir}")
    print(f"trained {iterations} iterations ({os.path.basename(checkpoint)}) in {wall:.0f} s of wall time")
    if style:
        print(
            f"style reward (TensorBoard points): first fifth {style['first_fifth_mean']:.3f} -> last fifth "
            f"{style['last_fifth_mean']:.3f}; lowest {style['min']:.3f} at {style['min_at_fraction']:.0%} of the run,"
            f" last {style['last']:.3f} ({style['count']} points; every tenth: {style['points']})"
        )
    if episodes:
        print(f"episode length [steps]: {episodes['first_fifth_mean']:.1f} -> {episodes['last_fifth_mean']:.1f}")
    print(
        f"played ({args.eval_envs} envs, {args.eval_seconds} s): joint RMS error to the nearest clip frame "
        f"{play['joint_rms_error_rad']:.3f} rad (standing zero pose: {play['zero_pose_joint_rms_error_rad']:.3f}); "
        f"forward speed {play['forward_speed_m_s']:.3f} m/s (horizontal {play['horizontal_speed_m_s']:.3f}, "
        f"clip {play['clip_forward_speed_m_s']:.3f}); {play['falls_per_env_minute']:.2f} falls per env-minute"
    )
    if sheet:
        print(f"play video: {videos[-1]}; six of its frames: {sheet}")
    if args.json:
        with open(args.json, "w") as f:
            json.dump(results, f, indent=2)
    return 0


if __name__ == "__main__":
    sys.exit(main())
