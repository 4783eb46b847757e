"""Agility Digit loco-manipulation tracking (Isaac Lab's ``Isaac-Tracking-LocoManip-Digit-v0``): the task
builds and steps on the CPU, its hand commands and rewards name the wrist bodies, its criterion measures
the hands where they are and fails an untrained policy, the arms' action range reaches the commanded hand
positions, and Isaac Lab's own task file runs after the import mapping with the same terms."""

from __future__ import annotations

import importlib
import importlib.util
import sys
from pathlib import Path

import gymnasium as gym
import mujoco
import numpy as np
import pytest
import torch

import simlab.tasks  # noqa: F401 - registers the tasks
import simlab.utils.math as math_utils
from simlab.envs import ManagerBasedRLEnv
from simlab.robots.agility import ASSETS_DIR
from simlab.tasks.manager_based.locomanipulation.tracking.criterion import HAND_MAX_POSITION_ERROR
from simlab.tasks.utils.criteria import criterion_for
from simlab.tasks.utils.parse_cfg import load_cfg_from_registry, parse_env_cfg
from simlab.utils.string import resolve_matching_names_values

TASK = "simlab/Tracking-LocoManip-Digit-v0"
HANDS = {"left_ee_pose": "left_arm_wrist_yaw", "right_ee_pose": "right_arm_wrist_yaw"}
N = 2
# 9 (base velocities, gravity) + 3 (velocity command) + 2 x 7 (hand poses) + 3 x 26 motors
OBS_DIM = 9 + 3 + 14 + 78


def make(task: str = TASK, hand_window_s: float | None = None, num_envs: int = N) -> ManagerBasedRLEnv:
    cfg = parse_env_cfg(task, device="cpu", num_envs=num_envs)
    cfg.seed = 0
    if hand_window_s is not None:
        for name in HANDS:
            getattr(cfg.commands, name).resampling_time_range = (hand_window_s, hand_window_s)
    return gym.make(task, cfg=cfg).unwrapped


def steps_finite(env: ManagerBasedRLEnv, steps: int = 20) -> None:
    obs, _ = env.reset()
    for _ in range(steps):
        obs, reward, *_ = env.step(0.3 * torch.randn(N, env.action_manager.total_action_dim))
        assert torch.isfinite(obs["policy"]).all() and torch.isfinite(reward).all()


@pytest.mark.parametrize("task", [TASK, "simlab/Tracking-LocoManip-Digit-Play-v0"])
def test_task_builds_and_steps(task):
    spec = gym.spec(task)
    assert spec.kwargs["success_criterion_entry_point"].endswith("tracking.criterion:tracks_velocity_and_hands")
    assert spec.kwargs["rsl_rl_cfg_entry_point"].endswith(":DigitLocoManipPPORunnerCfg")
    env = make(task)
    try:
        assert env.action_manager.total_action_dim == 26
        assert env.observation_manager.group_obs_dim["policy"] == (OBS_DIM,)
        assert env.max_episode_length_s == 14.0
        for name, body in HANDS.items():
            term = env.command_manager.get_term(name)
            assert env.scene["robot"].body_names[term.body_idx] == body
        terms = env.reward_manager.active_terms
        assert "joint_deviation_arms" not in terms and "joint_vel_hip_yaw" in terms
        assert {f"{side}_ee_pos_tracking" for side in ("left", "right")} <= set(terms)
        assert env.reward_manager.get_term_cfg("flat_orientation_l2").weight == -10.5
        # the velocity task's __post_init__ sets the velocity command's ranges, as in Isaac Lab
        velocity = env.command_manager.get_term("base_velocity").cfg
        assert velocity.ranges.lin_vel_x == (-0.8, 0.8) and velocity.heading_command
        steps_finite(env)
    finally:
        env.close()


def hand_pose_in_root_frame(env: ManagerBasedRLEnv, body: str) -> torch.Tensor:
    data = env.scene["robot"].data
    index = env.scene["robot"].body_names.index(body)
    pos, quat = math_utils.subtract_frame_transforms(
        data.root_pos_w, data.root_quat_w, data.body_pos_w[:, index], data.body_quat_w[:, index]
    )
    return torch.cat([pos, quat], dim=-1)


def test_criterion_measures_the_hands_and_fails_an_untrained_policy():
    criterion = criterion_for(TASK)
    env = make(hand_window_s=0.3)  # windows that end before the untrained robot falls (about 1 s)
    try:
        env.reset()
        zero = torch.zeros(N, env.action_manager.total_action_dim)

        # commands set to where the hands are: no hand error at the windows' ends
        on_target, state = criterion.make_hook()
        for _ in range(150):
            obs, *_ = env.step(zero)
            for name, body in HANDS.items():
                env.command_manager.get_term(name).pose_command_b[:] = hand_pose_in_root_frame(env, body)
            on_target(env, obs, zero)
        assert state["hand_errors"], "no hand command window ended"
        assert float(torch.cat(state["hand_errors"]).max()) < 1e-4

        # the hands left hanging and the robot left to fall: fails, the hands' error far over 0.1 m
        hook, state = criterion.make_hook()
        env.reset()  # fresh commands
        for _ in range(150):
            obs, *_ = env.step(zero)
            hook(env, obs, zero)
        score, passed = criterion.judge({}, state)
        assert not passed and score > 1.0
        assert float(torch.cat(state["hand_errors"]).mean()) > 0.2
        # the judge's log names what the score is the largest of (each error over its tolerance)
        parts = state["parts"]
        assert parts["hand_m"] == pytest.approx(float(torch.cat(state["hand_errors"]).mean()))
        assert score == pytest.approx(
            max(parts["speed_m_s"] / 0.25, parts["yaw_rate_rad_s"] / 0.3, parts["hand_m"] / 0.1)
        )
    finally:
        env.close()


def test_the_arms_start_with_the_hands_in_the_middle_of_their_commands():
    """The default arm pose (the untrained policy's hands) puts each hand at the middle of its command
    box in the commands' middle orientation (level, turned 90 degrees out of the torso's yaw). Hanging
    straight in a torso-aligned frame, the hands were 0.42 m and 90 degrees from their commands."""
    env = make()
    try:
        env.reset()
        for name, body in HANDS.items():
            ranges = getattr(env.cfg.commands, name).ranges
            middle = torch.tensor([sum(r) / 2 for r in (ranges.pos_x, ranges.pos_y, ranges.pos_z)])
            rpy = torch.tensor([[sum(r) / 2 for r in (ranges.roll, ranges.pitch, ranges.yaw)]])
            pose = hand_pose_in_root_frame(env, body)
            assert torch.linalg.norm(pose[:, :3] - middle, dim=-1).max() < 0.01, pose[:, :3]
            wanted = math_utils.quat_from_euler_xyz(rpy[:, 0], rpy[:, 1], rpy[:, 2]).expand(N, 4)
            assert math_utils.quat_error_magnitude(pose[:, 3:], wanted).max() < 0.02
    finally:
        env.close()


def test_staying_alive_pays_at_the_agents_initial_action_noise():
    """PPO's first actions are Gaussian noise of the runner's init_std about the default pose. A fall
    costs the termination penalty once (weight x dt); a second alive costs whatever the other terms sum
    to. Putting a fall off by a step earns that step's reward and discounts the penalty by gamma once
    more, so below termination weight x (1 - gamma) = -1 per second PPO learns to end episodes rather
    than to balance. Measured here over 3 s (each robot falls after 1.2-1.6 s and starts again): -2.9 per
    second with the hands hanging in a torso-aligned frame and noise 1.0 (0.5: -2.3), -1.6 with the hands
    at their commands' middle and noise 1.0, -0.8 at 0.5. Digit's flat velocity task, which learns at
    noise 1.0: +0.3."""
    agent = load_cfg_from_registry(TASK, "rsl_rl_cfg_entry_point")
    std, gamma = agent.actor.distribution_cfg.init_std, agent.algorithm.gamma
    n = 32
    cfg = parse_env_cfg(TASK, device="cpu", num_envs=n)
    cfg.seed = 0
    penalty = cfg.rewards.termination_penalty.weight
    env = gym.make(TASK, cfg=cfg).unwrapped
    try:
        env.reset()
        torch.manual_seed(0)
        alive, falls = 0.0, 0
        for _ in range(150):
            _, reward, terminated, _, _ = env.step(std * torch.randn(n, env.action_manager.total_action_dim))
            alive += float((reward - penalty * env.step_dt * terminated.float()).sum())
            falls += int(terminated.sum())
        assert falls >= n, "each robot falls at least once: the noise is PPO's first, not a policy's"
        per_second = alive / (150 * n * env.step_dt)
        bar = penalty * (1.0 - gamma)
        assert per_second > bar, f"alive: {per_second:.2f} per second, falling pays below {bar:.2f}"
    finally:
        env.close()


def arm_joints(side: str) -> list[str]:
    joints = ("shoulder_pitch", "shoulder_roll", "shoulder_yaw", "elbow", "wrist_roll", "wrist_pitch", "wrist_yaw")
    return [f"{side}_arm_{joint}" for joint in joints]


LEFT_ARM = arm_joints("left")


class ArmKinematics:
    """One arm of the MJCF with the torso at the origin, upright, the legs at zero (which do not move
    the torso frame, the frame of the hand commands)."""

    def __init__(self, side: str):
        self.model = mujoco.MjModel.from_xml_path(ASSETS_DIR + "/agility_digit.xml")
        self.data = mujoco.MjData(self.model)
        self.joints = arm_joints(side)
        self.qpos = [self.model.joint(name).qposadr[0] for name in self.joints]
        self.dofs = [self.model.joint(name).dofadr[0] for name in self.joints]
        self.range = np.array([self.model.jnt_range[self.model.joint(name).id] for name in self.joints])
        self.hand = self.model.body(f"{side}_arm_wrist_yaw").id
        self.jacobian = np.zeros((3, self.model.nv))

    def position(self, q: np.ndarray) -> np.ndarray:
        """The hand's position with the arm's joints at ``q``."""
        self.data.qpos[:] = 0.0
        self.data.qpos[3] = 1.0  # the torso at the origin, upright
        self.data.qpos[self.qpos] = q
        mujoco.mj_kinematics(self.model, self.data)
        mujoco.mj_comPos(self.model, self.data)  # the Jacobian needs it
        return self.data.xpos[self.hand].copy()

    def solve(self, target: np.ndarray, q: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
        """Joints within [lo, hi] that bring the hand nearest ``target``: damped least squares from ``q``,
        projected on the box."""
        for _ in range(40):
            error = target - self.position(q)
            mujoco.mj_jacBody(self.model, self.data, self.jacobian, None, self.hand)
            j = self.jacobian[:, self.dofs]
            q = np.clip(q + j.T @ np.linalg.solve(j @ j.T + 1e-4 * np.eye(3), error), lo, hi)
        return q


def hand_reach(lo: np.ndarray, hi: np.ndarray, targets: np.ndarray, seed: int = 0) -> np.ndarray:
    """Distance [m] from each target (in the torso's frame) to the nearest position the left hand takes
    with its arm's joints within [lo, hi]: damped least squares from the box's middle and from the
    nearest of 2,000 random arm poses in it, on the MJCF."""
    arm = ArmKinematics("left")
    poses = np.random.default_rng(seed).uniform(lo, hi, (2000, len(lo)))
    reached = np.array([arm.position(q) for q in poses])
    distances = []
    for target in targets:
        starts = ((lo + hi) / 2, poses[np.argmin(((reached - target) ** 2).sum(1))])
        ends = [arm.solve(target, q, lo, hi) for q in starts]
        distances.append(min(float(np.linalg.norm(target - arm.position(q))) for q in ends))
    return np.array(distances)


def test_the_arms_action_range_reaches_the_commanded_hand_positions():
    """Within three units of action of the default pose the left hand comes within 5 cm of at least half
    the commanded positions (62 % of these 60 from the forearm-forward pose, 50 % within one unit; 63 %
    and 13 % from the arm hanging; with its joints unbounded the arm reaches 70 % of 300, most of the
    rest lying beyond its length from the shoulder). The velocity task's motor-model scale (0.04-0.08
    rad per unit) reached none of these 60 from the hanging arm (docs/locomotion.md)."""
    cfg = parse_env_cfg(TASK, device="cpu", num_envs=1)
    _, _, scale = resolve_matching_names_values(
        cfg.actions.joint_pos.scale, LEFT_ARM, preserve_order=True, strict=False
    )
    _, _, default = resolve_matching_names_values(
        cfg.scene.robot.init_state.joint_pos, LEFT_ARM, preserve_order=True, strict=False
    )
    joint_range = ArmKinematics("left").range
    ranges = cfg.commands.left_ee_pose.ranges
    rng = np.random.default_rng(0)
    targets = np.stack(
        [rng.uniform(*ranges.pos_x, 60), rng.uniform(*ranges.pos_y, 60), rng.uniform(*ranges.pos_z, 60)], 1
    )
    reach = 3.0 * np.array(scale)
    lo = np.maximum(np.array(default) - reach, joint_range[:, 0])
    hi = np.minimum(np.array(default) + reach, joint_range[:, 1])
    distances = hand_reach(lo, hi, targets)
    assert np.mean(distances < 0.05) >= 0.5, np.mean(distances < 0.05)


def test_arms_driven_to_each_command_by_inverse_kinematics_meet_the_hand_bar():
    """End to end through the env and its criterion: for each new hand command, the arm's joints that
    bring the hand nearest it on the MJCF with the torso at the origin (the commands' frame), within three
    units of action of the default pose, given as the task's arm actions (legs at zero: the robot stands
    about 1.4 s, falls and starts again). At the ends of 0.6 s windows the criterion measures the hands
    0.04 m from their commands (held still: 0.20 m), under its 0.1 m bar, and the hand terms pay +1.5 per
    second against -0.8 with the arms held still. Read as a world-frame offset, the commands leave the
    reaching hands 0.6 m off and this fails. With the shipped flat Digit policy walking the legs (32 robots,
    20 s, the task's 1-3 s windows) the hands end 0.05-0.07 m off and a robot alive earns +4.4 per second
    against +2.2 with its arms still (scripts/benchmarks/digit_locomanip_scripted.py, docs/locomotion.md)."""
    criterion = criterion_for(TASK)
    n, steps = 8, 75
    env = make(hand_window_s=0.6, num_envs=n)
    try:
        robot = env.scene["robot"]
        action_cfg = env.cfg.actions.joint_pos
        names = robot.find_joints(action_cfg.joint_names)[1]
        default = robot.data.default_joint_pos[0, robot.find_joints(names, preserve_order=True)[0]]
        hand_terms = [
            i for i, name in enumerate(env.reward_manager.active_terms) if "end_effector" in name or "ee_" in name
        ]

        arms = {side: ArmKinematics(side) for side in ("left", "right")}
        columns = {side: [names.index(joint) for joint in arm.joints] for side, arm in arms.items()}
        scale = {
            side: np.array(resolve_matching_names_values(action_cfg.scale, arm.joints, strict=False)[2])
            for side, arm in arms.items()
        }

        def run(reach: bool) -> tuple[float, float]:
            """Mean hand error at the windows' ends [m], hand terms' reward per second."""
            hook, state = criterion.make_hook()
            env.reset()
            actions = torch.zeros(n, env.action_manager.total_action_dim)
            solved = {side: np.full((n, 3), np.nan) for side in arms}
            paid = 0.0
            for _ in range(steps):
                for side, arm in arms.items():
                    start = default[columns[side]].double().numpy()
                    lo = np.maximum(start - 3.0 * scale[side], arm.range[:, 0])
                    hi = np.minimum(start + 3.0 * scale[side], arm.range[:, 1])
                    targets = env.command_manager.get_command(f"{side}_ee_pose")[:, :3].double().numpy()
                    for e in np.flatnonzero((targets != solved[side]).any(axis=1)):  # new commands only
                        q = arm.solve(targets[e], start, lo, hi) if reach else start
                        actions[e, columns[side]] = torch.tensor((q - start) / scale[side], dtype=torch.float32)
                        solved[side][e] = targets[e]
                obs, *_ = env.step(actions)
                hook(env, obs, actions)
                paid += float(env.reward_manager._step_reward[:, hand_terms].sum()) / n
            return float(torch.cat(state["hand_errors"]).mean()), paid / steps

        reached, reached_pay = run(reach=True)
        still, still_pay = run(reach=False)
        assert reached < HAND_MAX_POSITION_ERROR < still, (reached, still)
        assert reached_pay > still_pay + 1.0, (reached_pay, still_pay)
    finally:
        env.close()


def test_the_scripted_policies_benchmark_runs(monkeypatch, capsys):
    """scripts/benchmarks/digit_locomanip_scripted.py (the shipped flat policy's legs, IK arms) prints each
    term's reward per second alive and the criterion's parts."""
    path = Path(__file__).parents[1] / "scripts" / "benchmarks" / "digit_locomanip_scripted.py"
    spec = importlib.util.spec_from_file_location("digit_locomanip_scripted", path)
    script = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(script)
    monkeypatch.setattr(sys, "argv", ["x", "--legs", "flat", "--arms", "ik", "--envs", "2", "--seconds", "0.4"])
    script.main()
    out = capsys.readouterr().out
    assert "left_ee_pos_tracking" in out and "hand_m" in out and "score" in out


def ported_cfg():
    path = str(Path(__file__).parent / "ported")
    sys.path.insert(0, path)
    try:
        env_module = importlib.import_module("isaaclab_locomanip_digit.loco_manip_env_cfg")
        agent_module = importlib.import_module("isaaclab_locomanip_digit.agents.rsl_rl_ppo_cfg")
    finally:
        sys.path.remove(path)
    return env_module.DigitLocoManipEnvCfg(), agent_module.DigitLocoManipPPORunnerCfg()


def test_isaac_labs_own_task_config_runs_after_the_import_mapping():
    cfg, agent = ported_cfg()
    ours = parse_env_cfg(TASK, device="cpu", num_envs=N)
    weights = {name: term.weight for name, term in vars(cfg.rewards).items() if term is not None}
    assert weights == {name: term.weight for name, term in vars(ours.rewards).items() if term is not None}
    for name in ("base_velocity", "left_ee_pose", "right_ee_pose"):
        assert getattr(cfg.commands, name).ranges == getattr(ours.commands, name).ranges
    ours_agent = gym.spec(TASK).kwargs["rsl_rl_cfg_entry_point"]
    module, _, name = ours_agent.partition(":")
    theirs, ours_dict = agent.to_dict(), getattr(importlib.import_module(module), name)().to_dict()
    # the one difference: the initial action noise (test_staying_alive_pays_at_the_agents_initial_action_noise)
    assert theirs["actor"]["distribution_cfg"].pop("init_std") == 1.0
    assert ours_dict["actor"]["distribution_cfg"].pop("init_std") == 0.5
    assert theirs == ours_dict
    cfg.scene.num_envs, cfg.sim.device, cfg.seed = N, "cpu", 0
    env = ManagerBasedRLEnv(cfg)
    try:
        assert env.observation_manager.group_obs_dim["policy"] == (OBS_DIM,)
        steps_finite(env, 5)
    finally:
        env.close()
