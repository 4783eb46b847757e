"""Can Reach-Franka-IK-Rel's action reach the commanded pose? A scripted proportional controller says.

    python scripts/benchmarks/ik_rel_scripted_reach.py --gains 0.2 0.5 1.0

Each step sends ``gain * (pose error) / scale`` through the task's relative differential-IK action
(position error and the rotation vector from the hand to the commanded orientation, both in the robot's
base frame): a gain g closes the fraction g of the error per step. Reports the mean position and
orientation errors just before each 4 s command resample, as the reach criterion judges them. If this
controller meets the criterion and a trained policy does not, the policy is what falls short, not the
action or the IK.
"""

from __future__ import annotations

import argparse

import gymnasium as gym
import torch

import simlab.tasks  # noqa: F401  (registers the tasks)
from simlab.tasks.utils import parse_env_cfg
from simlab.utils import math as math_utils

TASK = "simlab/Reach-Franka-IK-Rel-v0"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--gains", type=float, nargs="+", default=[0.2, 0.5, 1.0])
    parser.add_argument("--num_envs", type=int, default=64)
    parser.add_argument("--windows", type=int, default=4, help="Command windows judged (after a first one).")
    args = parser.parse_args()

    for gain in args.gains:
        env = gym.make(TASK, cfg=parse_env_cfg(TASK, device="cpu", num_envs=args.num_envs)).unwrapped
        env.reset()
        arm = env.action_manager.get_term("arm_action")
        window = round(4.0 / env.step_dt)
        position_errors, orientation_errors = [], []
        for step in range((args.windows + 1) * window):
            command = env.command_manager.get_command("ee_pose")
            ee_pos, ee_quat = arm._ee_pose_b()
            to_command = math_utils.quat_mul(command[:, 3:7], math_utils.quat_inv(ee_quat))
            rotation = math_utils.axis_angle_from_quat(to_command)
            env.step(gain * torch.cat([command[:, :3] - ee_pos, rotation], dim=-1) / arm.cfg.scale)
            if step >= window and step % window == window - 2:  # the last step before the resample
                ee_pos, ee_quat = arm._ee_pose_b()
                command = env.command_manager.get_command("ee_pose")
                position_errors.append(float((command[:, :3] - ee_pos).norm(dim=-1).mean()))
                orientation_errors.append(float(math_utils.quat_error_magnitude(command[:, 3:7], ee_quat).mean()))
        env.close()
        print(
            f"gain {gain}: position error (m) per window {[round(e, 4) for e in position_errors]}, "
            f"orientation error (rad) {[round(e, 3) for e in orientation_errors]}; "
            f"mean {sum(position_errors) / len(position_errors):.4f} m, "
            f"{sum(orientation_errors) / len(orientation_errors):.3f} rad"
        )


if __name__ == "__main__":
    main()
