"""Where a lift policy falls short of the criterion: never grasped, lifted but off the goal, or dropped.

    python scripts/benchmarks/lift_error_breakdown.py --log_root logs/lift --task simlab/Lift-Cube-Franka-IK-Rel-v0
    python scripts/benchmarks/lift_error_breakdown.py --log_root logs/lift --eval_envs 128 --eval_seconds 11

Plays the newest rsl_rl checkpoint under ``--log_root`` (its mean actions, seed 12345) and follows every
episode that runs to its time limit. The criterion (the lift task's ``criterion.py``) asks that >= 80 % of
the episodes end with the cube within 5 cm of its commanded position; this says where the others end:

* the share of episodes ending within 5 cm of the goal (the criterion's score, episodes ended by a
  termination counted as failed), and the shares ending lifted (cube centre above the lift reward's
  ``minimal_height``) or still on the table;
* the cube-to-goal distance at the end (median, for lifted episodes) and the closest it came during the
  episode: near at some point but not at the end means the policy gets there and does not hold it;
* the hand-to-cube distance at the end for episodes whose cube is still on the table (a hand far from
  the cube has not found it; a hand at the cube has not closed on it or lifted it).
"""

from __future__ import annotations

import argparse
import sys

import torch

from simlab.cli.main import build_parser
from simlab.cli.play import run_play

TASK = "simlab/Lift-Cube-Franka-v0"  # --task: or one of its IK variants
TOLERANCE_M = 0.05  # the criterion's


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--log_root", required=True)
    parser.add_argument("--task", default=TASK, help="The lift task the run trained (its IK variants too).")
    parser.add_argument("--device", default="cpu")
    parser.add_argument("--eval_envs", type=int, default=64)
    parser.add_argument("--eval_seconds", type=float, default=11.0, help="Two 5 s episodes and a margin.")
    parser.add_argument("overrides", nargs="*", help="env.x=v overrides the run was trained with.")
    args = parser.parse_args(argv)

    ended: list[torch.Tensor] = []  # per finished episode: goal distance, closest, lifted, hand distance
    state: dict[str, torch.Tensor] = {}
    counts = {"terminated": 0}

    def on_step(env, obs, actions) -> None:
        from simlab.tasks.manager_based.manipulation.lift import mdp
        from simlab.utils.math import combine_frame_transforms

        robot, cube = env.scene["robot"], env.scene["object"]
        command = env.command_manager.get_command("object_pose")
        goal_w, _ = combine_frame_transforms(robot.data.root_pos_w, robot.data.root_quat_w, command[:, :3])
        goal_distance = torch.linalg.norm(goal_w - cube.data.root_pos_w, dim=1)
        # a step that starts a new episode (its step counter at 1) starts its closest distance afresh
        fresh = env.episode_length_buf <= 1
        closest = state.get("closest", goal_distance.clone())
        closest = torch.where(fresh, goal_distance, torch.minimum(closest, goal_distance))
        state["closest"] = closest
        counts["terminated"] += int(env.termination_manager.terminated.sum())
        last = env.episode_length_buf >= env.max_episode_length - 1
        if not bool(last.any()):
            return
        lift_term = env.reward_manager.get_term_cfg("lifting_object")
        lifted = mdp.object_is_lifted(env, **lift_term.params) > 0
        hand_w = env.scene["ee_frame"].data.target_pos_w[..., 0, :]
        hand_distance = torch.linalg.norm(hand_w - cube.data.root_pos_w, dim=1)
        rows = torch.stack([goal_distance, closest, lifted.float(), hand_distance], dim=-1)
        ended.append(rows[last].cpu())

    argv = ["play", "--task", args.task, "--library", "rsl_rl", "--use_last_checkpoint", "--headless"]
    argv += ["--num_envs", str(args.eval_envs), "--log_root", args.log_root, "--no_export", "--seed", "12345"]
    argv += ["--device", args.device, "--seconds", str(args.eval_seconds)]
    play_args = build_parser().parse_args(argv)
    result = run_play(play_args, args.overrides, on_step=on_step)
    if not ended:
        print("no episode ran to its time limit: play longer (--eval_seconds)")
        return 1
    data = torch.cat(ended)
    goal, closest, lifted, hand = data[:, 0], data[:, 1], data[:, 2] > 0, data[:, 3]
    episodes = len(data) + counts["terminated"]
    within = goal < TOLERANCE_M
    print(f"\n{result['checkpoint']}: {len(data)} episodes ran to their time limit, {counts['terminated']} ended early")
    print(f"criterion score (ended within {TOLERANCE_M * 100:.0f} cm of the goal): {int(within.sum()) / episodes:.3f}")
    print(f"ended lifted: {lifted.float().mean():.3f}; ended on the table: {(~lifted).float().mean():.3f}")
    if lifted.any():
        reached = float((closest[lifted] < TOLERANCE_M).float().mean())
        print(
            f"lifted episodes: goal distance at the end median {goal[lifted].median() * 100:.1f} cm, "
            f"closest during the episode median {closest[lifted].median() * 100:.1f} cm; "
            f"within {TOLERANCE_M * 100:.0f} cm at some point {reached:.3f}"
        )
    if (~lifted).any():
        print(f"episodes on the table: hand-to-cube distance at the end median {hand[~lifted].median() * 100:.1f} cm")
    return 0


if __name__ == "__main__":
    sys.exit(main())
