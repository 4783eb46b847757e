"""Stack the three cubes with a scripted pick-and-place state machine (simlab's; Isaac Lab records this
task by teleoperation and Mimic).

Each env runs its own machine: pick cube 2 and place it on cube 1, then pick cube 3 and place it on
cube 2. The machine aims the hand at absolute poses (the IK-Abs task's actions); on a task whose arm
takes relative poses (IK-Rel, also the instance-randomized one) :func:`task_actions` turns each aim into
a delta pose from where the hand is, clipped to a step. Each pick turns the fingers square to the
cube's faces. A move ends when the fingertips are near enough its target (or after its most steps), a
gripper's open or close after a few steps: the machine's next action follows from what the task observes, so a
policy cloned from its demonstrations can tell when to close the gripper. The script judges the run
by the task's registered criterion (the share of episodes that end with the cubes stacked) and
prints it; with ``--dataset_file`` it records the episodes that end stacked with simlab's recorder
(scripts/imitation_learning/bc.py clones a policy from them), and besides the ``actions`` it applied
(with ``--noise``) the machine's own actions before the noise as ``clean_actions`` (the label to clone).

    python scripts/environments/state_machine/stack_cube_sm.py --num_envs 8 --headless --device cpu
    python scripts/environments/state_machine/stack_cube_sm.py --num_envs 8 --headless --device cpu \
        --task simlab/Stack-Cube-Instance-Randomize-Franka-IK-Rel-v0
"""

from __future__ import annotations

import argparse
import math
import os
from collections.abc import Callable

import torch

import simlab.utils.math as math_utils
from simlab.utils.math import quat_from_euler_xyz, quat_mul, yaw_quat

TASK = "simlab/Stack-Cube-Franka-IK-Abs-v0"
"""The default task; any stack task whose ``arm_action`` is a differential-IK pose (IK-Abs or IK-Rel)."""
MAX_STEP = (0.1, 0.5)
"""The most a relative action moves the hand in one step: position [m], rotation [rad]."""
TCP_OFFSET = 0.1034
"""The fingertip centre below the hand [m] (the task's end-effector frame)."""
LIFT_HEIGHT = 0.15
"""Height of the fingertips above the table [m] a picked cube is lifted to."""
HAND_DOWN = (0.0, 1.0, 0.0, 0.0)
"""The hand's orientation with its z axis (the fingers) pointing down."""

# (name, most steps it lasts, gripper command: 1 open, -1 closed, a move's reach: it ends once the
# fingertips are this close to its target [m], 0 for the gripper's states). The grasp starts 12 mm
# from the cube's centre, the hand still going down while the fingers close: a wide region where a
# cloned policy learns to close. The gripper's states last while its fingers move (they close on a
# cube in 2 steps), so no state repeats one the machine has already left.
PHASES = (
    ("above_pick", 30, 1.0, 0.02),
    ("at_pick", 30, 1.0, 0.012),
    ("grasp", 2, -1.0, 0.0),
    ("lift", 30, -1.0, 0.02),
    ("above_place", 40, -1.0, 0.015),
    ("lower", 30, -1.0, 0.01),
    ("release", 3, 1.0, 0.0),
    ("retreat", 20, 1.0, 0.02),
)
PAIRS = (("cube_2", "cube_1"), ("cube_3", "cube_2"))
"""(the cube picked, the cube it is placed on), in order."""


class StackCubesSm:
    """One pick-and-place machine per env, in torch: ``compute`` gives the IK-Abs actions (hand pose in
    the env frame, gripper) from the cubes' poses; ``reset_idx`` starts envs over."""

    def __init__(self, num_envs: int, cube_size: float, device: torch.device | str = "cpu"):
        self.num_envs, self.cube_size, self.device = num_envs, cube_size, device
        self.state = torch.zeros(num_envs, dtype=torch.long, device=device)  # phase index over both pairs
        self.waited = torch.zeros(num_envs, dtype=torch.long, device=device)
        self.grasp_yaw = torch.zeros(num_envs, device=device)
        self.steps = torch.tensor([p[1] for p in PHASES] * len(PAIRS), device=device)
        self.gripper = torch.tensor([p[2] for p in PHASES] * len(PAIRS), device=device)
        self.reach = torch.tensor([p[3] for p in PHASES] * len(PAIRS), device=device)
        self.down = torch.tensor(HAND_DOWN, device=device)
        self.target = torch.zeros(num_envs, 3, device=device)  # of the fingertips, by the last compute()

    @property
    def done(self) -> torch.Tensor:
        return self.state >= len(PHASES) * len(PAIRS)

    def reset_idx(self, env_ids: torch.Tensor | None = None) -> None:
        ids = slice(None) if env_ids is None else env_ids
        self.state[ids], self.waited[ids] = 0, 0

    def compute(self, cube_pos: dict[str, torch.Tensor], cube_quat: dict[str, torch.Tensor]) -> torch.Tensor:
        """(num_envs, 8) actions from the cubes' positions (env frame) and orientations."""
        state = self.state.clamp(max=len(PHASES) * len(PAIRS) - 1)
        pair, phase = state // len(PHASES), state % len(PHASES)
        picked = torch.where(pair[:, None] == 0, cube_pos[PAIRS[0][0]], cube_pos[PAIRS[1][0]])
        below = torch.where(pair[:, None] == 0, cube_pos[PAIRS[0][1]], cube_pos[PAIRS[1][1]])
        picked_quat = torch.where(pair[:, None] == 0, cube_quat[PAIRS[0][0]], cube_quat[PAIRS[1][0]])
        # before grasping, follow the picked cube's yaw folded into +-45 degrees (a cube looks the same
        # every quarter turn)
        yaw = 2 * torch.atan2(yaw_quat(picked_quat)[:, 3], yaw_quat(picked_quat)[:, 0])
        folded = torch.remainder(yaw + math.pi / 4, math.pi / 2) - math.pi / 4
        self.grasp_yaw = torch.where(phase < 2, folded, self.grasp_yaw)

        up = torch.zeros_like(picked)
        up[:, 2] = 1.0
        on_below = below + up * (self.cube_size + 0.004)
        # lift to a fixed height, not above the picked cube (which rises with the hand): a target a
        # policy cloned from these demonstrations can reach without the machine's step counts
        lifted = torch.cat([picked[:, :2], torch.full_like(picked[:, 2:], LIFT_HEIGHT)], dim=1)
        targets = torch.stack(
            [
                picked + up * 0.1,
                picked,
                picked,
                lifted,
                on_below + up * 0.06,
                on_below,
                on_below,
                on_below + up * 0.1,
            ],
            dim=1,
        )
        self.target = targets[torch.arange(self.num_envs, device=self.device), phase]
        hand = self.target + up * TCP_OFFSET
        zeros = torch.zeros_like(self.grasp_yaw)
        quat = quat_mul(quat_from_euler_xyz(zeros, zeros, self.grasp_yaw), self.down.expand(self.num_envs, 4))
        gripper = self.gripper[state].unsqueeze(-1)
        return torch.cat([hand, quat, gripper], dim=-1)

    def advance(self, tip: torch.Tensor) -> None:
        """Count one step; move on where a move's target is reached (``tip``: the fingertips' position,
        env frame) or the state has lasted its most steps."""
        running = ~self.done
        self.waited += running.long()
        state = self.state.clamp(max=len(self.steps) - 1)
        reached = torch.linalg.vector_norm(tip - self.target, dim=-1) < self.reach[state]
        finished = running & (reached | (self.waited >= self.steps[state]))
        self.state += finished.long()
        self.waited[finished] = 0


def task_actions(env, actions: torch.Tensor, max_step: tuple[float, float] = MAX_STEP) -> torch.Tensor:
    """The env's actions for the machine's (hand pose in the robot's root frame, gripper): as they are
    where the ``arm_action`` takes absolute poses; where it takes relative ones, the pose error from
    its end-effector frame now to that frame on the aimed hand, translation and rotation vector each
    clipped to ``max_step`` (m, rad) in length and divided by the term's scale (after its offset)."""
    term = env.action_manager.get_term("arm_action")
    if not term.cfg.controller.use_relative_mode:
        return actions
    pos, quat = term._ee_pose_b()  # the frame the action moves, as the term reads it (root frame)
    aim_pos, aim_quat = actions[:, :3], actions[:, 3:7]
    if term.cfg.body_offset is not None:  # that frame is at the offset from the body
        offset = term.cfg.body_offset
        offset_pos = torch.tensor(offset.pos, device=actions.device).expand_as(pos)
        offset_rot = torch.tensor(offset.rot, device=actions.device).expand_as(quat)
        aim_pos, aim_quat = math_utils.combine_frame_transforms(aim_pos, aim_quat, offset_pos, offset_rot)
    delta = torch.cat(math_utils.compute_pose_error(pos, quat, aim_pos, aim_quat), dim=-1)
    for part, most in zip((delta[:, :3], delta[:, 3:]), max_step):
        part *= most / torch.linalg.vector_norm(part, dim=-1, keepdim=True).clamp(min=most)
    scale = torch.as_tensor(term.cfg.scale, device=actions.device)
    offset = torch.as_tensor(term.cfg.offset, device=actions.device)
    return torch.cat([(delta - offset) / scale, actions[:, 7:]], dim=-1)


def run(
    env,
    steps: int,
    watch: Callable[[dict], None] | None = None,
    noise: float = 0.0,
    stop: Callable[[], bool] | None = None,
    task: str = TASK,
) -> tuple[StackCubesSm, dict[str, int]]:
    """Step ``env`` (the stack ``task``) ``steps`` times under the machine, or until ``stop()``; returns
    it and the criterion's counts (episodes, and those that ended stacked). ``watch`` sees each step's
    observations; ``noise`` [m] is the std of a Gaussian offset added to each aimed hand position
    (demonstrations that show how to come back from small errors). Each step's action without the
    noise goes to the env's recorder as ``clean_actions``."""
    from simlab.managers import SceneEntityCfg
    from simlab.tasks.manager_based.manipulation.stack.config.franka.stack_joint_pos_env_cfg import CUBE_SIZE
    from simlab.tasks.manager_based.manipulation.stack.mdp.observations import object_pose_w
    from simlab.tasks.utils.criteria import criterion_for

    on_step, counts = criterion_for(task).make_hook()
    machine = StackCubesSm(env.num_envs, CUBE_SIZE, env.device)
    origins = env.scene.env_origins
    # each cube, or the one in focus where the cubes are collections (the instance-randomized task)
    cubes = {n: SceneEntityCfg(n) for n in ("cube_1", "cube_2", "cube_3")}
    for _ in range(steps):
        if stop is not None and stop():
            break
        poses = {n: object_pose_w(env, cfg) for n, cfg in cubes.items()}
        aims = machine.compute({n: p - origins for n, (p, _) in poses.items()}, {n: q for n, (_, q) in poses.items()})
        actions = clean = task_actions(env, aims)
        if noise > 0:
            noisy = torch.cat([aims[:, :3] + noise * torch.randn_like(aims[:, :3]), aims[:, 3:]], dim=-1)
            actions = task_actions(env, noisy)
        env.recorder_manager.add_to_episodes("clean_actions", clean)
        obs, _, terminated, truncated, _ = env.step(actions)
        on_step(env, obs, actions)
        if watch is not None:
            watch(obs)
        machine.advance(env.scene["ee_frame"].data.target_pos_w[:, 0] - origins)
        ended = (terminated | truncated).nonzero().flatten()
        if len(ended):
            machine.reset_idx(ended)
    return machine, counts


def main() -> None:
    from simlab.app import AppLauncher

    parser = argparse.ArgumentParser(description="Stack the cubes with a scripted state machine.")
    parser.add_argument("--num_envs", type=int, default=8, help="Number of environments to simulate.")
    parser.add_argument(
        "--steps", type=int, default=240, help="Env steps to run (0.05 s each); with --dataset_file: until --num_demos."
    )
    parser.add_argument("--seed", type=int, default=0, help="Seed of the environment.")
    parser.add_argument(
        "--dataset_file",
        default=None,
        help="Record the episodes that end stacked into this HDF5 file (simlab's recorder).",
    )
    parser.add_argument("--num_demos", type=int, default=10, help="With --dataset_file: stop once this many are in.")
    parser.add_argument("--noise", type=float, default=0.0, help="Std [m] of noise on the commanded hand position.")
    parser.add_argument("--task", default=TASK, help="A stack task whose arm takes IK-Abs or IK-Rel poses.")
    AppLauncher.add_app_launcher_args(parser)
    args = parser.parse_args()
    if args.dataset_file is not None and (os.path.exists(args.dataset_file) or not args.dataset_file.endswith(".hdf5")):
        parser.error(f"--dataset_file must be a new .hdf5 file, got {args.dataset_file}")
    if args.num_demos < 1 or args.noise < 0:
        parser.error(f"--num_demos must be >= 1 and --noise >= 0, got {args.num_demos} and {args.noise}")
    AppLauncher(args)

    import gymnasium as gym

    import simlab.tasks  # noqa: F401 - registers the tasks
    from simlab.cli.demos import add_demo_recorders
    from simlab.tasks.utils.criteria import criterion_for
    from simlab.tasks.utils.parse_cfg import parse_env_cfg

    cfg = parse_env_cfg(args.task, device=args.device, num_envs=args.num_envs)
    arm = getattr(cfg.actions, "arm_action", None)
    if getattr(getattr(arm, "controller", None), "command_type", None) != "pose":
        parser.error(f"--task {args.task} has no differential-IK pose arm_action: give an IK-Abs or IK-Rel stack task")
    cfg.seed = args.seed
    steps, stop = args.steps, None
    if args.dataset_file is not None:
        add_demo_recorders(cfg, args.dataset_file, args.task, succeeded_only=True)
    env = gym.make(args.task, cfg=cfg).unwrapped
    if args.dataset_file is not None:  # until enough episodes ended stacked; at most two 30 s episodes per demo and env
        manager = env.recorder_manager
        steps = 2 * int(env.max_episode_length) * (1 + args.num_demos // args.num_envs)
        stop = lambda: manager.exported_successful_episode_count >= args.num_demos  # noqa: E731
    env.reset()
    with torch.inference_mode():
        _, counts = run(env, steps, noise=args.noise, stop=stop, task=args.task)
    score, passed = criterion_for(args.task).judge({}, counts)
    print(
        f"[simlab] {counts['success']} of {counts['episodes']} finished episodes ended stacked ({score:.0%});"
        f" the criterion {'passes' if passed else 'fails'}"
    )
    if args.dataset_file is not None:
        print(
            f"[simlab] recorded {manager.exported_successful_episode_count} stacking demonstrations"
            f" into {args.dataset_file}"
        )
    env.close()


if __name__ == "__main__":
    main()
