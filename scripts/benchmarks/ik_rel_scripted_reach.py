"""Can Reach-Franka-IK-Rel's action reach the commanded pose? A scripted proportional controller says.

    python scripts/benchmarks/ik_rel_scripted_reach.py --gains 0.2 0.5 1.0

The command is a pose of ``panda_hand``; the action moves the IK frame 0.107 m further along the hand's
z. Each step sends ``gain * (pose error) / scale`` through the task's relative differential-IK action
(the IK frame's position error to where the commanded hand pose puts it, and the rotation vector to the
commanded orientation, both in the robot's base frame): a gain g closes the fraction g of the error per
step. Reports the hand's mean position and orientation errors (the task's reward terms) just before
each 4 s command resample, as the reach criterion judges them. If this
controller meets the criterion and a trained policy does not, the policy is what falls short, not the
action or the IK.
"""

from __future__ import annotations

import argparse

import gymnasium as gym
import torch

import simlab.tasks  # noqa: F401  (registers the tasks)
from simlab.managers import SceneEntityCfg
from simlab.tasks.manager_based.manipulation.reach import mdp
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
        hand = SceneEntityCfg("robot", body_names=["panda_hand"])
        hand.resolve(env.scene)
        offset = torch.tensor(arm.cfg.body_offset.pos).expand(env.num_envs, 3)
        window = round(4.0 / env.step_dt)
        position_errors, orientation_errors = [], []
        for step in range((args.windows + 1) * window):
            command = env.command_manager.get_command("ee_pose")
            ee_pos, ee_quat = arm._ee_pose_b()
            to_command = math_utils.quat_mul(command[:, 3:7], math_utils.quat_inv(ee_quat))
            rotation = math_utils.axis_angle_from_quat(to_command)
            target_pos = command[:, :3] + math_utils.quat_apply(command[:, 3:7], offset)
            env.step(gain * torch.cat([target_pos - ee_pos, rotation], dim=-1) / arm.cfg.scale)
            if step >= window and step % window == window - 2:  # the last step before the resample
                position_errors.append(float(mdp.position_command_error(env, "ee_pose", hand).mean()))
                orientation_errors.append(float(mdp.orientation_command_error(env, "ee_pose", hand).mean()))
        env.close()
        print(
            f"gain {gain}: position error (m) per window {[round(e, 4) for e in position_errors]}, "
            f"orientation error (rad) {[round(e, 3) for e in orientation_errors]}; "
            f"mean {sum(position_errors) / len(position_errors):.4f} m, "
            f"{sum(orientation_errors) / len(orientation_errors):.3f} rad"
        )


if __name__ == "__main__":
    main()
