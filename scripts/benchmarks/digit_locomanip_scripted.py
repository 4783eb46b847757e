"""What Digit loco-manipulation's rewards and criterion give scripted policies (issue 41).

The legs: the shipped ``simlab/Velocity-Flat-Digit-v0`` policy (fed its own observations: the task's
without the hand commands, the arms' joints relative to its default, its own last action), zero, or
Gaussian noise. The arms: held at the task's default pose, driven to each hand command by inverse
kinematics on the MJCF (the torso at the origin, the commands' frame; within three units of action,
at most ``--rate`` units of action per step), or Gaussian noise. It prints each reward term per second
alive, the falls, and the criterion's score with its parts (speed, yaw-rate and hand errors)::

    .venv/bin/python scripts/benchmarks/digit_locomanip_scripted.py --legs flat --arms ik --envs 32 --seconds 20

A GPU score near 2.0 with the hand part near 0.2 m is a robot that walks and leaves its arms at the
default pose; near 2.7, one that falls (docs/locomotion.md).
"""

from __future__ import annotations

import argparse

import gymnasium as gym
import mujoco
import numpy as np
import torch

import simlab.tasks  # noqa: F401 - registers the tasks
from simlab.pretrained import pretrained_run_dir
from simlab.pretrained.isaaclab_policies import MLPPolicy, actor_state
from simlab.pretrained.weights import unpack_policy
from simlab.robots.agility import ASSETS_DIR
from simlab.tasks.utils.criteria import criterion_for
from simlab.tasks.utils.parse_cfg import parse_env_cfg
from simlab.utils.string import resolve_matching_names_values

TASK = "simlab/Tracking-LocoManip-Digit-v0"
FLAT = "simlab/Velocity-Flat-Digit-v0"
ARM = ("shoulder_pitch", "shoulder_roll", "shoulder_yaw", "elbow", "wrist_roll", "wrist_pitch", "wrist_yaw")


class ArmIK:
    """Damped least squares for one hand's position, the torso at the origin, joints within a box."""

    def __init__(self, side: str):
        self.model = mujoco.MjModel.from_xml_path(ASSETS_DIR + "/agility_digit.xml")
        self.data = mujoco.MjData(self.model)
        self.joints = [f"{side}_arm_{joint}" for joint in ARM]
        self.qpos = [self.model.joint(name).qposadr[0] for name in self.joints]
        self.dofs = [self.model.joint(name).dofadr[0] for name in self.joints]
        self.range = np.array([self.model.jnt_range[self.model.joint(name).id] for name in self.joints])
        self.hand = self.model.body(f"{side}_arm_wrist_yaw").id
        self.jacobian = np.zeros((3, self.model.nv))

    def solve(self, target: np.ndarray, q: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
        for _ in range(40):
            self.data.qpos[:] = 0.0
            self.data.qpos[3] = 1.0
            self.data.qpos[self.qpos] = q
            mujoco.mj_kinematics(self.model, self.data)
            mujoco.mj_comPos(self.model, self.data)
            mujoco.mj_jacBody(self.model, self.data, self.jacobian, None, self.hand)
            j = self.jacobian[:, self.dofs]
            error = target - self.data.xpos[self.hand]
            q = np.clip(q + j.T @ np.linalg.solve(j @ j.T + 1e-4 * np.eye(3), error), lo, hi)
        return q


def noise_std(spec: str) -> float | None:
    return float(spec.split(":", 1)[1]) if spec.startswith("noise:") else None


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--legs", default="flat", help="flat | zero | noise:<std>")
    parser.add_argument("--arms", default="still", help="still | ik | noise:<std>")
    parser.add_argument("--envs", type=int, default=32)
    parser.add_argument("--seconds", type=float, default=20.0)
    parser.add_argument("--rate", type=float, default=0.2, help="ik: most units of arm action per step")
    parser.add_argument("--obs_noise", action="store_true", help="the task's observation noise (off: as played)")
    parser.add_argument("--engine", default="mujoco", help="mujoco | mujoco_warp (Warp's CPU device)")
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()

    cfg = parse_env_cfg(TASK, device="cpu", num_envs=args.envs)
    cfg.seed, cfg.sim.engine = args.seed, args.engine
    cfg.observations.policy.enable_corruption = args.obs_noise
    env = gym.make(TASK, cfg=cfg).unwrapped
    criterion = criterion_for(TASK)
    hook, state = criterion.make_hook()
    n, robot, action_cfg = args.envs, env.scene["robot"], cfg.actions.joint_pos
    names = robot.find_joints(action_cfg.joint_names)[1]  # the action's joints, in its order
    default = robot.data.default_joint_pos[0, robot.find_joints(names, preserve_order=True)[0]]
    scale = torch.tensor(resolve_matching_names_values(action_cfg.scale, names)[2])
    arm = torch.tensor(["_arm_" in name for name in names])

    # the flat policy's observation: this task's terms it reads, its arms relative to its default pose
    flat_pose = parse_env_cfg(FLAT, device="cpu", num_envs=1).scene.robot.init_state.joint_pos
    flat_default = resolve_matching_names_values(flat_pose, names, strict=False)[2]  # passive joints left out
    offset = default - torch.tensor(flat_default)
    terms = env.observation_manager.active_terms["policy"]
    ends = np.cumsum([dim[0] for dim in env.observation_manager.group_obs_term_dim["policy"]])
    span = {term: slice(end - dim, end) for term, end, dim in zip(terms, ends, np.diff(np.r_[0, ends]), strict=True)}
    _, state_dict = unpack_policy(pretrained_run_dir(FLAT, "rsl_rl") + "/policy.pt")
    flat_policy = MLPPolicy(actor_state(state_dict, FLAT), "elu", FLAT)
    flat_last = torch.zeros(n, len(names))

    arms = {side: ArmIK(side) for side in ("left", "right")}
    columns = {side: [names.index(joint) for joint in ik.joints] for side, ik in arms.items()}
    solved = {side: np.full((n, 3), np.nan) for side in arms}
    goal = torch.zeros(n, len(names))

    torch.manual_seed(args.seed)
    obs, _ = env.reset()
    actions = torch.zeros(n, len(names))
    steps = round(args.seconds / env.step_dt)
    per_term = torch.zeros(len(env.reward_manager.active_terms))
    alive_steps = falls = 0
    for _ in range(steps):
        legs = arm_actions = torch.zeros(n, len(names))
        if args.legs == "flat":
            o = obs["policy"]
            parts = [o[:, span[t]] for t in ("base_lin_vel", "base_ang_vel", "projected_gravity", "velocity_commands")]
            parts += [o[:, span["joint_pos"]] + offset, o[:, span["joint_vel"]], flat_last]
            with torch.no_grad():
                flat_last = flat_policy(torch.cat(parts, dim=1))
            legs = flat_last
        elif noise_std(args.legs) is not None:
            legs = noise_std(args.legs) * torch.randn(n, len(names))
        if args.arms == "ik":
            for side, ik in arms.items():
                start = default[columns[side]].double().numpy()
                reach = 3.0 * scale[columns[side]].double().numpy()
                lo, hi = np.maximum(start - reach, ik.range[:, 0]), np.minimum(start + reach, ik.range[:, 1])
                targets = env.command_manager.get_command(f"{side}_ee_pose")[:, :3].double().numpy()
                for e in np.flatnonzero((targets != solved[side]).any(axis=1)):  # new commands only
                    q = torch.tensor(ik.solve(targets[e], start, lo, hi), dtype=torch.float32)
                    goal[e, columns[side]] = (q - default[columns[side]]) / scale[columns[side]]
                    solved[side][e] = targets[e]
            arm_actions = actions + (goal - actions).clamp(-args.rate, args.rate)
        elif noise_std(args.arms) is not None:
            arm_actions = noise_std(args.arms) * torch.randn(n, len(names))
        actions = torch.where(arm, arm_actions, legs)
        obs, _, terminated, _, _ = env.step(actions)
        hook(env, obs, actions)
        alive = ~terminated
        per_term += env.reward_manager._step_reward[alive].sum(dim=0)  # weighted, per second
        alive_steps += int(alive.sum())
        falls += int(terminated.sum())

    print(f"{TASK}: legs {args.legs}, arms {args.arms}, {n} envs x {args.seconds:.0f} s, engine {args.engine}")
    print(f"falls: {falls}")
    rates = per_term / max(alive_steps, 1)
    for name, rate in zip(env.reward_manager.active_terms, rates.tolist(), strict=True):
        print(f"  {name:42s} {rate:+.3f} per second alive")
    counted = [t != "termination_penalty" for t in env.reward_manager.active_terms]
    print(f"  {'all but the termination penalty':42s} {float(rates[counted].sum()):+.3f} per second alive")
    score, passed = criterion.judge({}, state)
    parts = ", ".join(f"{k} {v:.3f}" for k, v in state["parts"].items())
    print(f"score {score:.3f} ({'passes' if passed else 'fails'}): {parts}")
    env.close()


if __name__ == "__main__":
    main()
