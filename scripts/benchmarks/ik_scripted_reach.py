"""Can the reach task's differential-IK action reach the commanded pose? A scripted controller says.

    python scripts/benchmarks/ik_scripted_reach.py --gains 0.2 0.5 1.0          # Reach-Franka-IK-Rel-v0
    python scripts/benchmarks/ik_scripted_reach.py --task simlab/Reach-Franka-IK-Abs-v0

The command is a pose of ``panda_hand``; the action moves the IK frame 0.107 m further along the hand's
z, so the scripted target is where the commanded hand pose puts that frame, in the robot's base frame.
IK-Rel: each step sends ``gain * (pose error) / scale`` (the position error and the rotation vector to
the commanded orientation): a gain g closes the fraction g of the error per step. IK-Abs: each step
sends the target pose itself, through the action's offset and scale (``--gains`` is not used).
Reports the hand's mean position and orientation errors (the task's reward terms) just before each
4 s command resample, as the reach criterion judges them. If this controller meets the criterion and
a trained policy does not, the policy is what falls short, not the action or the IK.
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

TASKS = ("simlab/Reach-Franka-IK-Rel-v0", "simlab/Reach-Franka-IK-Abs-v0")


def scripted_action(arm, command: torch.Tensor, offset: torch.Tensor, gain: float) -> torch.Tensor:
    """The action that sends the IK frame to the commanded pose (IK-Abs) or ``gain`` of the way (IK-Rel)."""
    target_pos = command[:, :3] + math_utils.quat_apply(command[:, 3:7], offset)
    scale = torch.as_tensor(arm.cfg.scale, dtype=command.dtype)
    if not arm.cfg.controller.use_relative_mode:
        pose = torch.cat([target_pos, command[:, 3:7]], dim=-1)
        return (pose - torch.as_tensor(arm.cfg.offset, dtype=command.dtype)) / scale
    ee_pos, ee_quat = arm._ee_pose_b()
    rotation = math_utils.axis_angle_from_quat(math_utils.quat_mul(command[:, 3:7], math_utils.quat_inv(ee_quat)))
    return gain * torch.cat([target_pos - ee_pos, rotation], dim=-1) / scale


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--task", choices=TASKS, default=TASKS[0])
    parser.add_argument("--gains", type=float, nargs="+", default=[0.2, 0.5, 1.0], help="IK-Rel's gains.")
    parser.add_argument("--num_envs", type=int, default=64)
    parser.add_argument("--windows", type=int, default=4, help="Command windows judged (after a first one).")
    args = parser.parse_args()

    for gain in args.gains if args.task.endswith("IK-Rel-v0") else [None]:
        env = gym.make(args.task, cfg=parse_env_cfg(args.task, device="cpu", num_envs=args.num_envs)).unwrapped
        env.reset()
        arm = env.action_manager.get_term("arm_action")
        hand = SceneEntityCfg("robot", body_names=["panda_hand"])
        hand.resolve(env.scene)
        offset = torch.tensor(arm.cfg.body_offset.pos).expand(env.num_envs, 3)
        window = round(4.0 / env.step_dt)
        position_errors, orientation_errors = [], []
        for step in range((args.windows + 1) * window):
            env.step(scripted_action(arm, env.command_manager.get_command("ee_pose"), offset, gain))
            if step >= window and step % window == window - 2:  # the last step before the resample
                position_errors.append(float(mdp.position_command_error(env, "ee_pose", hand).mean()))
                orientation_errors.append(float(mdp.orientation_command_error(env, "ee_pose", hand).mean()))
        env.close()
        print(
            f"{args.task}{f' gain {gain}' if gain is not None else ''}: position error (m) per window "
            f"{[round(e, 4) for e in position_errors]}, orientation error (rad) "
            f"{[round(e, 3) for e in orientation_errors]}; mean {sum(position_errors) / len(position_errors):.4f} m, "
            f"{sum(orientation_errors) / len(orientation_errors):.3f} rad"
        )


if __name__ == "__main__":
    main()
