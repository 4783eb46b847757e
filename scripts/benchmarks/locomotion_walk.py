"""Does the Go2 learn to walk? Train ``simlab/Velocity-Flat-Unitree-Go2-v0`` with rsl_rl, then play
the policy with fixed commands and measure how well it tracks them (issue 12, item 6).

    python scripts/benchmarks/locomotion_walk.py --device cuda --num_envs 4096 --max_iterations 300
    python scripts/benchmarks/locomotion_walk.py --device cpu --num_envs 8 --max_iterations 2 --play_seconds 1

Each command (forward 0.5 and 1.0 m/s, sideways 0.5 m/s, turning 1 rad/s) is played for
``--play_seconds`` on ``--play_envs`` envs of the task's play config (no observation noise, no
pushes). Reported per command, averaged over envs and over the steps after the first
``--settle_seconds`` (the policy starts each play from a standstill):

* planar velocity error: ``|v_xy command - v_xy|`` in the base frame [m/s] (target <= 0.2)
* yaw-rate error: ``|w_z command - w_z|`` [rad/s] (target <= 0.3)
* fall fraction: envs whose episode ended in a termination (base contact) (target < 2 %)

With ``--video PATH`` the first command's play is also rendered (env 0) to an mp4.
"""

from __future__ import annotations

import argparse
import os
import sys
import time

import gymnasium as gym
import torch
from rsl_rl.runners import OnPolicyRunner

import simlab.tasks  # noqa: F401 - registers the tasks
from simlab.rl.rsl_rl import RslRlVecEnvWrapper
from simlab.tasks.utils.parse_cfg import load_cfg_from_registry, parse_env_cfg

TASK = "simlab/Velocity-Flat-Unitree-Go2-v0"
PLAY_TASK = "simlab/Velocity-Flat-Unitree-Go2-Play-v0"
COMMANDS = {
    "forward 0.5 m/s": (0.5, 0.0, 0.0),
    "forward 1.0 m/s": (1.0, 0.0, 0.0),
    "sideways 0.5 m/s": (0.0, 0.5, 0.0),
    "turning 1 rad/s": (0.0, 0.0, 1.0),
}


def train(args: argparse.Namespace) -> tuple[OnPolicyRunner, float]:
    env_cfg = parse_env_cfg(TASK, device=args.device, num_envs=args.num_envs)
    env_cfg.seed = args.seed
    agent_cfg = load_cfg_from_registry(TASK, "rsl_rl_cfg_entry_point")
    agent_cfg.seed = args.seed
    agent_cfg.device = args.device
    if args.max_iterations is not None:
        agent_cfg.max_iterations = args.max_iterations
    env = RslRlVecEnvWrapper(gym.make(TASK, cfg=env_cfg), clip_actions=agent_cfg.clip_actions)
    log_dir = os.path.join(args.log_root, "locomotion_walk", time.strftime("%Y-%m-%d_%H-%M-%S"))
    runner = OnPolicyRunner(env, agent_cfg.to_rsl_rl_dict(), log_dir=log_dir, device=args.device)
    start = time.time()
    runner.learn(num_learning_iterations=agent_cfg.max_iterations, init_at_random_ep_len=True)
    wall = time.time() - start
    runner.save(os.path.join(log_dir, "model_final.pt"))
    print(f"trained {agent_cfg.max_iterations} iterations on {args.num_envs} envs in {wall:.1f} s; {log_dir}")
    env.close()
    return runner, wall


def play_command(policy, args: argparse.Namespace, command: tuple[float, float, float], video: str | None) -> dict:
    """Play ``command`` on fresh envs; the mean errors after the settling time and the falls."""
    cfg = parse_env_cfg(PLAY_TASK, device=args.device, num_envs=args.play_envs)
    cfg.seed = args.seed
    vel = cfg.commands.base_velocity
    vel.heading_command = False
    vel.rel_standing_envs = 0.0
    vel.resampling_time_range = (1.0e9, 1.0e9)
    vel.ranges.lin_vel_x = (command[0], command[0])
    vel.ranges.lin_vel_y = (command[1], command[1])
    vel.ranges.ang_vel_z = (command[2], command[2])
    cfg.episode_length_s = args.play_seconds + 1.0  # no time-outs inside the measured window
    cfg.viewer.origin_type, cfg.viewer.asset_name = "asset_root", "robot"  # the video follows env 0
    cfg.viewer.eye, cfg.viewer.lookat = (1.2, -1.2, 0.6), (0.0, 0.0, 0.0)
    render_mode = "rgb_array" if video else None
    env = RslRlVecEnvWrapper(gym.make(PLAY_TASK, cfg=cfg, render_mode=render_mode))
    base = env.unwrapped
    robot = base.scene["robot"]
    target = torch.tensor(command, device=base.device)
    steps = round(args.play_seconds / base.step_dt)
    settle = round(args.settle_seconds / base.step_dt)
    fallen = torch.zeros(base.num_envs, dtype=torch.bool, device=base.device)
    vel_error = torch.zeros((), device=base.device)
    yaw_error = torch.zeros((), device=base.device)
    frames = []
    obs = env.get_observations()
    with torch.inference_mode():
        for step in range(steps):
            obs, _, dones, extras = env.step(policy(obs))
            fallen |= (dones > 0) & ~extras["time_outs"].bool()
            if step >= settle:
                vel_error += torch.linalg.norm(robot.data.root_lin_vel_b[:, :2] - target[:2], dim=1).mean()
                yaw_error += (robot.data.root_ang_vel_b[:, 2] - target[2]).abs().mean()
            if video:
                frames.append(base.render())
    measured = max(1, steps - settle)
    if video:
        import imageio

        imageio.mimsave(video, frames, fps=round(1.0 / base.step_dt))
        print(f"video: {video}")
    env.close()
    return {
        "vel_error": float(vel_error) / measured,
        "yaw_error": float(yaw_error) / measured,
        "fall_fraction": float(fallen.float().mean()),
    }


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--num_envs", type=int, default=4096)
    parser.add_argument("--max_iterations", type=int, default=None, help="Default: the agent config's (300).")
    parser.add_argument("--device", default="cuda" if torch.cuda.is_available() else "cpu")
    parser.add_argument("--seed", type=int, default=42)
    parser.add_argument("--play_envs", type=int, default=64)
    parser.add_argument("--play_seconds", type=float, default=20.0)
    parser.add_argument("--settle_seconds", type=float, default=1.0)
    parser.add_argument("--log_root", default="logs")
    parser.add_argument("--video", default=None, help="Write the first command's play (env 0) to this mp4.")
    args = parser.parse_args()

    runner, wall = train(args)
    policy = runner.get_inference_policy(device=args.device)
    rows = []
    for i, (name, command) in enumerate(COMMANDS.items()):
        result = play_command(policy, args, command, args.video if i == 0 else None)
        rows.append((name, result))

    print(f"\n{TASK}: {args.num_envs} envs, training wall time {wall:.1f} s on {args.device}")
    print(f"play: {args.play_envs} envs x {args.play_seconds} s per command, errors after {args.settle_seconds} s")
    print(f"{'command':<18} {'|v_xy err| [m/s]':>16} {'|w_z err| [rad/s]':>17} {'falls':>7}")
    ok = True
    for name, r in rows:
        print(f"{name:<18} {r['vel_error']:>16.3f} {r['yaw_error']:>17.3f} {r['fall_fraction']:>7.1%}")
        ok &= r["vel_error"] <= 0.2 and r["yaw_error"] <= 0.3 and r["fall_fraction"] < 0.02
    mean_vel = sum(r["vel_error"] for _, r in rows) / len(rows)
    mean_yaw = sum(r["yaw_error"] for _, r in rows) / len(rows)
    falls = sum(r["fall_fraction"] for _, r in rows) / len(rows)
    print(f"{'mean':<18} {mean_vel:>16.3f} {mean_yaw:>17.3f} {falls:>7.1%}")
    print(f"criterion (<= 0.2 m/s, <= 0.3 rad/s, < 2 % falls, each command): {'PASS' if ok else 'FAIL'}")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
