"""Where a trained reach policy's error lies: direction, command region, and its course over training.

    python scripts/benchmarks/reach_error_breakdown.py --log_root logs/reach --device cuda:0
    python scripts/benchmarks/reach_error_breakdown.py --log_root logs/reach_ik --task simlab/Reach-Franka-IK-Abs-v0
    python scripts/benchmarks/reach_error_breakdown.py --log_root logs/reach_nograv \
        env.scene.robot.spawn.rigid_props.disable_gravity=True

Plays the newest rsl_rl checkpoint under ``--log_root`` on held-out commands (seed 12345, as
``manipulation_learn.py``) and reports, at the last step of every 4 s command window:

* the hand's position error (mean, median) and orientation error, as ``manipulation_learn.py`` judges them;
* the signed error in the robot's base frame (mean dx, dy, dz): gravity sag the policy failed to
  aim past shows as a negative dz, an imprecise reach as |dx| / |dy| with a mean near 0;
* the error for near (x <= 0.5 m) and far commands;
* the pull toward the centre of the command box, per axis: the slope ``k`` of the signed error on
  (centre - command); 0 follows the command, 1 ignores it (stays at the centre);
* position and orientation error by the command's yaw (the hand's yaw is mostly joint 7, whose
  +-2.9 rad range does not cover every commanded yaw: the commands near +-pi need the far end of it);
* the windows that ended with a joint within 0.05 rad of an end of its range: how many per joint, how
  many of them missed the commanded orientation by more than 0.2 rad, and their errors;
* from the run's TensorBoard events, ``Metrics/ee_pose/position_error`` over the iterations and the
  iteration at which the curriculum raised the action-rate penalty.

Overrides (``env.x=v``) must be the ones the run was trained with.
"""

from __future__ import annotations

import argparse
import glob
import math
import os
import sys

import torch

from simlab.cli.main import build_parser
from simlab.cli.play import run_play

TASK = "simlab/Reach-Franka-v0"  # --task: or one of its IK / OSC variants
MISSED_RAD = 0.2  # a window whose orientation error is above this missed the commanded orientation
AT_LIMIT_RAD = 0.05  # a joint this close to an end of its range is held there


def training_curve(log_root: str) -> list[str]:
    """Lines with the position error metric and the action-rate weight over the newest run's iterations."""
    from tensorboard.backend.event_processing.event_accumulator import EventAccumulator

    files = glob.glob(os.path.join(log_root, "**", "events.out.tfevents*"), recursive=True)
    if not files:
        return [f"no TensorBoard events under {log_root}"]
    events = EventAccumulator(max(files, key=os.path.getmtime))
    events.Reload()
    scalars = events.Tags()["scalars"]
    lines = []
    if "Metrics/ee_pose/position_error" in scalars:
        # the metric is logged when episodes end; iterations before the first end read 0
        points = [p for p in events.Scalars("Metrics/ee_pose/position_error") if p.value > 0]
        every = max(1, len(points) // 12)
        shown = points[::every] if (len(points) - 1) % every == 0 else points[::every] + points[-1:]
        curve = " ".join(f"{p.step}:{p.value * 100:.1f}" for p in shown)
        lines.append(f"training position error [cm] by iteration: {curve}")
    if "Curriculum/action_rate" in scalars:
        raised = [p.step for p in events.Scalars("Curriculum/action_rate") if p.value < -0.0001 - 1e-9]
        lines.append(f"curriculum raised the action-rate penalty at iteration {raised[0] if raised else 'never'}")
    return lines


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--log_root", required=True)
    parser.add_argument("--task", default=TASK, help="The reach task the run trained (its IK / OSC variants too).")
    parser.add_argument("--device", default="cpu")
    parser.add_argument("--eval_envs", type=int, default=256)
    parser.add_argument("--eval_seconds", type=float, default=20.0)
    parser.add_argument("overrides", nargs="*", help="env.x=v overrides the run was trained with.")
    args = parser.parse_args()

    # per ending window: signed position error (3), command xyz (3), angle, yaw, box centre (3), joint margins
    windows: list[torch.Tensor] = []
    joint_names: list[str] = []

    def on_step(env, obs, actions) -> None:
        from simlab.managers import SceneEntityCfg
        from simlab.tasks.manager_based.manipulation.reach import mdp
        from simlab.utils.math import euler_xyz_from_quat, subtract_frame_transforms

        term = env.command_manager.get_term("ee_pose")
        ending = term.time_left <= env.step_dt * 0.5
        if not bool(ending.any()):
            return
        robot = env.scene["robot"]
        asset_cfg = SceneEntityCfg("robot", body_names=[term.cfg.body_name])
        asset_cfg.resolve(env.scene)
        command = env.command_manager.get_command("ee_pose")[:, :3]
        hand_b, _ = subtract_frame_transforms(
            robot.data.root_pos_w, robot.data.root_quat_w, robot.data.body_pos_w[:, asset_cfg.body_ids[0]]
        )
        angle = mdp.orientation_command_error(env, "ee_pose", asset_cfg)
        _, _, yaw = euler_xyz_from_quat(env.command_manager.get_command("ee_pose")[:, 3:7])
        yaw = torch.remainder(yaw + math.pi, 2 * math.pi) - math.pi
        r = term.cfg.ranges
        centre = torch.tensor([sum(r.pos_x), sum(r.pos_y), sum(r.pos_z)], device=command.device) / 2
        # how near each joint is to its range's ends (a joint held at a limit can stop the hand short)
        limits = robot.data.joint_pos_limits
        margin = torch.minimum(robot.data.joint_pos - limits[..., 0], limits[..., 1] - robot.data.joint_pos)
        if not joint_names:
            joint_names.extend(robot.joint_names)
        rows = torch.cat(
            [hand_b - command, command, angle[:, None], yaw[:, None], centre.expand_as(command), margin], -1
        )
        windows.append(rows[ending].cpu())

    argv = ["play", "--task", args.task, "--library", "rsl_rl", "--use_last_checkpoint", "--headless"]
    argv += ["--num_envs", str(args.eval_envs), "--log_root", args.log_root, "--no_export", "--seed", "12345"]
    argv += ["--device", args.device]
    play_args = build_parser().parse_args(argv)
    play_args.steps = round(args.eval_seconds * 30)  # the reach env steps at 30 Hz
    run_play(play_args, args.overrides, on_step=on_step)
    if not windows:
        print("no command window ended: play longer (--eval_seconds)")
        return 1
    data = torch.cat(windows)
    error_cm, command, angle, yaw, centre = data[:, :3] * 100, data[:, 3:6], data[:, 6], data[:, 7], data[:, 8:11]
    margin = data[:, 11:]
    distance = error_cm.norm(dim=1)
    near = command[:, 0] <= 0.5
    print(f"\n{len(data)} command windows")
    print(
        f"position error mean {distance.mean():.2f} cm (median {distance.median():.2f}); "
        f"orientation error mean {angle.mean():.3f} rad (median {angle.median():.3f})"
    )
    signed = " ".join(f"{v:.2f}" for v in error_cm.mean(0).tolist())
    size = " ".join(f"{v:.2f}" for v in error_cm.abs().mean(0).tolist())
    print(f"signed error in the base frame, mean dx dy dz [cm]: {signed}; mean |dx| |dy| |dz| [cm]: {size}")
    print(
        f"commands x <= 0.5 m: {distance[near].mean():.2f} cm (n={int(near.sum())}); "
        f"x > 0.5 m: {distance[~near].mean():.2f} cm (n={int((~near).sum())})"
    )
    off_cm = (centre - command) * 100
    pull = (error_cm * off_cm).sum(0) / (off_cm**2).sum(0)
    print(
        "pull toward the command box's centre, k x y z (0: follows the command, 1: stays at the centre): "
        + " ".join(f"{v:.2f}" for v in pull.tolist())
    )
    edges = torch.linspace(-math.pi, math.pi, 9)
    for lo, hi in zip(edges[:-1].tolist(), edges[1:].tolist()):
        inside = (yaw >= lo) & (yaw < hi)
        if inside.any():
            print(
                f"  yaw [{lo:+.2f}, {hi:+.2f}) rad: position {distance[inside].mean():5.2f} cm, "
                f"orientation {angle[inside].mean():.3f} rad (n={int(inside.sum())})"
            )
    at_limit = margin < AT_LIMIT_RAD
    at_limit[:, at_limit.all(0)] = False  # a joint at its limit in every window (the open fingers) tells nothing
    missed = angle > MISSED_RAD
    print(f"{int(missed.sum())} windows missed the commanded orientation by more than {MISSED_RAD} rad")
    print(f"windows that ended with a joint within {AT_LIMIT_RAD} rad of a limit:")
    for j, joint in enumerate(joint_names):
        held = at_limit[:, j]
        if held.any():
            print(
                f"  {joint}: {int(held.sum())} windows, {int((held & missed).sum())} of them missed; position "
                f"{distance[held].mean():.2f} cm, orientation {angle[held].mean():.3f} rad"
            )
    for line in training_curve(args.log_root):
        print(line)
    return 0


if __name__ == "__main__":
    sys.exit(main())
