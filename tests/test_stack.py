"""Franka cube stacking (Isaac Lab's stack tasks): each task builds and steps, the cube layout keeps the
cubes apart, a scripted pick-and-place state machine stacks cube 2 on cube 1 with absolute IK actions
while the subtask signals flip in order, and ``simlab record`` stores the subtask signals."""

from __future__ import annotations

import sys
from pathlib import Path

import gymnasium as gym
import h5py
import pytest
import torch
from conftest import load_script

import simlab.tasks  # noqa: F401 - registers the tasks
from simlab.tasks.manager_based.manipulation.stack.config.franka.stack_joint_pos_env_cfg import CUBE_SIZE
from simlab.tasks.manager_based.manipulation.stack.mdp import sample_object_poses
from simlab.tasks.utils.criteria import criterion_for
from simlab.tasks.utils.parse_cfg import parse_env_cfg
from simlab.utils.math import quat_from_euler_xyz, quat_mul, yaw_quat

PORTED_STACK = Path(__file__).parent / "ported" / "isaaclab_stack_franka" / "stack_joint_pos_env_cfg.py"
TASKS = ["simlab/Stack-Cube-Franka-v0", "simlab/Stack-Cube-Franka-IK-Rel-v0", "simlab/Stack-Cube-Franka-IK-Abs-v0"]
SUBTASKS = ["grasp_1", "stack_1", "grasp_2"]


def make(task: str, num_envs: int = 2):
    cfg = parse_env_cfg(task, device="cpu", num_envs=num_envs)
    cfg.seed = 0
    return gym.make(task, cfg=cfg)


@pytest.mark.parametrize("task", TASKS)
def test_task_builds_and_steps(task):
    env = make(task)
    obs, _ = env.reset(seed=0)
    width = {"simlab/Stack-Cube-Franka-v0": 8, "simlab/Stack-Cube-Franka-IK-Rel-v0": 7}.get(task, 8)
    assert env.action_space.shape == (2, width)
    assert set(obs) == {"policy", "subtask_terms"}
    assert list(obs["subtask_terms"]) == SUBTASKS
    assert obs["policy"]["object"].shape == (2, 39) and obs["policy"]["cube_positions"].shape == (2, 9)
    for _ in range(5):
        obs, reward, terminated, truncated, _ = env.step(torch.zeros(env.action_space.shape))
    assert all(torch.isfinite(v).all() for v in obs["policy"].values())
    assert not any(obs["subtask_terms"][name].any() for name in SUBTASKS)  # nothing grasped or stacked yet
    assert not terminated.any() and not truncated.any()
    env.close()


RANGES = {"x": (0.4, 0.6), "y": (-0.1, 0.1), "z": (CUBE_SIZE / 2, CUBE_SIZE / 2), "yaw": (-1.0, 1, 0)}


def assert_apart_within_ranges(poses: torch.Tensor) -> None:
    """(envs, cubes, 6) poses in the env frame: 10 cm apart, inside the stack task's ranges."""
    positions = poses[..., :3]
    gaps = torch.cdist(positions, positions) + torch.eye(positions.shape[1])  # an object from itself: 1 m
    assert (gaps > 0.1).all(), gaps.min()
    for axis, key in enumerate("xyz"):
        low, high = RANGES[key][:2]
        assert (positions[..., axis] >= low - 1e-6).all() and (positions[..., axis] <= high + 1e-6).all(), key


def test_cube_layouts_keep_the_cubes_apart_within_the_range():
    poses = sample_object_poses(2000, 3, 0.1, RANGES, 128, "cpu")
    assert poses.shape == (2000, 3, 6)
    assert_apart_within_ranges(poses)
    assert (poses[..., 3:5] == 0).all()  # no roll or pitch range: none drawn
    assert (poses[..., 5].abs() <= 1.0).all() and poses[..., 5].std() > 0.3
    # the cubes are not piled into one corner: each axis spans most of its range
    assert poses[..., 0].max() - poses[..., 0].min() > 0.18 and poses[..., 1].max() - poses[..., 1].min() > 0.18
    with pytest.raises(ValueError, match="unknown key"):
        sample_object_poses(1, 3, 0.1, {"height": (0.0, 1.0)}, 4, "cpu")
    # where no draw can be far enough (two cubes in a 5 cm square), the last draw is kept, in range
    tight = sample_object_poses(50, 2, 0.1, {"x": (0.0, 0.05), "y": (0.0, 0.05)}, 8, "cpu")
    assert (tight[..., :2] >= 0).all() and (tight[..., :2] <= 0.05).all()


def test_the_reset_event_places_the_cubes_apart_within_the_range_in_the_envs_it_resets():
    env = make("simlab/Stack-Cube-Franka-v0", num_envs=16).unwrapped
    env.reset(seed=0)
    cubes = [env.scene[f"cube_{i}"] for i in (1, 2, 3)]
    actions = torch.zeros(16, env.action_manager.total_action_dim)
    for _ in range(3):
        before = torch.stack([cube.data.root_pos_w.clone() for cube in cubes], dim=1)
        env.episode_length_buf[::2] = env.max_episode_length  # the even envs time out in this step
        env.step(actions)
        after = torch.stack([cube.data.root_pos_w for cube in cubes], dim=1)
        local = after - env.scene.env_origins[:, None, :]
        assert_apart_within_ranges(torch.cat([local, torch.zeros_like(local)], dim=-1)[::2])
        assert not torch.equal(after[::2], before[::2])  # the reset envs got new layouts
        assert (after[1::2] - before[1::2]).norm(dim=-1).max() < 0.01  # the others' cubes stayed put
    env.close()


def test_the_tasks_register_the_stacking_criterion():
    for task in TASKS:
        assert "three cubes stacked" in criterion_for(task).description


# -- a scripted pick-and-place -------------------------------------------------------------------------

TCP = 0.1034  # fingertip centre below the hand [m]
DOWN = torch.tensor([0.0, 1.0, 0.0, 0.0])  # the hand's z axis pointing down


def pick_and_place_targets(state, cube, below, hand_yaw):
    """Fingertip target (env frame) and gripper command (1 open, -1 closed) of each state."""
    above_cube = cube + torch.tensor([0.0, 0.0, 0.1])
    on_below = below + torch.tensor([0.0, 0.0, CUBE_SIZE + 0.004])
    targets = [
        (above_cube, 1.0),  # 0: above cube 2
        (cube, 1.0),  # 1: around it
        (cube, -1.0),  # 2: grasp
        (cube + torch.tensor([0.0, 0.0, 0.12]), -1.0),  # 3: lift
        (on_below + torch.tensor([0.0, 0.0, 0.06]), -1.0),  # 4: above cube 1
        (on_below, -1.0),  # 5: lower onto it
        (on_below, 1.0),  # 6: release
        (on_below + torch.tensor([0.0, 0.0, 0.1]), 1.0),  # 7: retreat
    ]
    return targets[state]


def test_a_scripted_state_machine_stacks_cube_2_on_cube_1_and_the_subtask_signals_flip_in_order():
    env = make("simlab/Stack-Cube-Franka-IK-Abs-v0", num_envs=1).unwrapped
    obs, _ = env.reset()
    origin = env.scene.env_origins[0]
    robot = env.scene["robot"]
    hand = robot.find_bodies("panda_hand")[0][0]
    state, waited, first_true = 0, 0, {}
    grasp_yaw = None
    holds = [10, 12, 10, 15, 15, 12, 10, 10]  # steps each state lasts (0.05 s each)
    for step in range(200):
        cube_2 = env.scene["cube_2"].data.root_pos_w[0] - origin
        cube_1 = env.scene["cube_1"].data.root_pos_w[0] - origin
        if grasp_yaw is None:  # turn the fingers square to cube 2's faces
            yaw = torch.atan2(*reversed(yaw_quat(env.scene["cube_2"].data.root_quat_w)[0, [0, 3]].unbind()))
            grasp_yaw = 2 * yaw
        tip, gripper = pick_and_place_targets(state, cube_2 if state < 4 else cube_1, cube_1, grasp_yaw)
        quat = quat_mul(quat_from_euler_xyz(torch.zeros(1), torch.zeros(1), grasp_yaw.reshape(1)), DOWN[None])
        action = torch.cat([tip + torch.tensor([0.0, 0.0, TCP]), quat[0], torch.tensor([gripper])])[None]
        obs, _, terminated, truncated, _ = env.step(action)
        assert not (terminated | truncated).any(), f"the episode ended at step {step} (state {state})"
        for name in SUBTASKS:
            if bool(obs["subtask_terms"][name][0]) and name not in first_true:
                first_true[name] = step
        waited += 1
        if waited >= holds[state]:
            state, waited = state + 1, 0
            if state == len(holds):
                break
    hand_pos = robot.data.body_pos_w[0, hand] - origin
    gap = env.scene["cube_2"].data.root_pos_w[0] - env.scene["cube_1"].data.root_pos_w[0]
    assert gap[:2].norm() < 0.02 and abs(gap[2] - CUBE_SIZE) < 0.005, f"cube 2 is at {gap} from cube 1"
    assert hand_pos[2] > 0.15  # the hand left the stack
    assert "grasp_1" in first_true and "stack_1" in first_true, first_true
    assert first_true["grasp_1"] < first_true["stack_1"]
    assert "grasp_2" not in first_true  # cube 3 was never touched
    assert bool(obs["subtask_terms"]["stack_1"][0]) and not bool(obs["subtask_terms"]["grasp_1"][0])
    env.close()


def test_simlab_record_stores_the_subtask_signals_and_the_demo_replays(tmp_path, capsys):
    from simlab.cli.main import main

    dataset = tmp_path / "stack.hdf5"
    argv = ["record", "--task", "simlab/Stack-Cube-Franka-IK-Rel-v0", "--num_envs", "1", "--device", "cpu"]
    argv += ["--headless", "--dataset_file", str(dataset), "--num_demos", "1", "env.episode_length_s=0.5"]
    assert main(argv) == 0
    with h5py.File(dataset) as file:
        demo = file["data/demo_0"]
        steps = demo["actions"].shape[0]
        assert steps == 10  # 0.5 s of 0.05 s steps
        signals = demo["obs/subtask_term_signals"]
        assert sorted(signals) == sorted(SUBTASKS)
        assert all(signals[name].shape == (steps,) for name in SUBTASKS)
        assert "cube_positions" in demo["obs"] and demo["obs/cube_positions"].shape == (steps, 9)
    replay = ["replay", "--task", "simlab/Stack-Cube-Franka-IK-Rel-v0", "--device", "cpu", "--headless"]
    assert main([*replay, "--dataset_file", str(dataset), "--validate_states"]) == 0  # bit-identical


def test_isaac_labs_stack_config_runs_after_the_import_mapping():
    """``tests/ported/isaaclab_stack_franka/stack_joint_pos_env_cfg.py`` is Isaac Lab's Franka stack
    config with its imports mapped: its block USDs spawn simlab's cubes, its gripper joints come from
    its gripper action, and it configures the actions and observations of simlab's own task."""
    from simlab.envs import ManagerBasedRLEnv
    from simlab.tasks.manager_based.manipulation.stack.config.franka.stack_joint_pos_env_cfg import (
        FrankaCubeStackEnvCfg,
    )

    ported = load_script(PORTED_STACK, "isaaclab_stack_joint_pos_env_cfg")
    try:
        cfg, ours = ported.FrankaCubeStackEnvCfg(), FrankaCubeStackEnvCfg()
        assert cfg.actions.to_dict() == ours.actions.to_dict()
        assert cfg.observations.to_dict() == ours.observations.to_dict()
        assert cfg.terminations.to_dict() == ours.terminations.to_dict()
        cfg.scene.num_envs, cfg.sim.device, cfg.seed = 2, "cpu", 0
        env = ManagerBasedRLEnv(cfg)
        obs, _ = env.reset()
        for _ in range(10):
            obs, *_ = env.step(torch.zeros(2, 8))
        heights = torch.stack([env.scene[f"cube_{i}"].data.root_pos_w[:, 2] for i in (1, 2, 3)])
        torch.testing.assert_close(heights, torch.full_like(heights, CUBE_SIZE / 2), atol=1e-3, rtol=0)
        torch.testing.assert_close(obs["policy"]["gripper_pos"], torch.tensor([[0.04, -0.04]] * 2), atol=1e-3, rtol=0)
        assert not any(obs["subtask_terms"][name].any() for name in SUBTASKS)
        env.close()
    finally:
        sys.modules.pop("isaaclab_stack_joint_pos_env_cfg", None)


@pytest.mark.parametrize("gripper", [1.0, -1.0])
def test_a_stack_of_three_ends_the_episode_as_a_success_and_the_criterion_counts_it(gripper):
    """A tower of the three cubes in env 0 is a success once the gripper is open, not while it closes."""
    env = make("simlab/Stack-Cube-Franka-v0").unwrapped
    env.reset()
    on_step, counts = criterion_for("simlab/Stack-Cube-Franka-v0").make_hook()
    origin = env.scene.env_origins[0]
    base = torch.tensor([0.5, 0.0, CUBE_SIZE / 2]) + origin
    for level, name in enumerate(("cube_1", "cube_2", "cube_3")):  # a tower in env 0 only
        pose = torch.cat([base + torch.tensor([0.0, 0.0, level * CUBE_SIZE]), torch.tensor([1.0, 0.0, 0.0, 0.0])])
        env.scene[name].write_root_pose_to_sim(pose[None], env_ids=torch.tensor([0]))
    for _ in range(10):
        actions = torch.zeros(env.num_envs, 8)  # arm at its default pose
        actions[:, -1] = gripper
        obs, _, terminated, _, _ = env.step(actions)
        on_step(env, obs, actions)
        if terminated.any():
            break
    if gripper < 0:
        assert not terminated.any() and counts == {"success": 0, "episodes": 0}
        return
    assert terminated.tolist() == [True, False]
    assert env.termination_manager.get_term("success").tolist() == [True, False]
    assert counts == {"success": 1, "episodes": 1}
    score, passed = criterion_for("simlab/Stack-Cube-Franka-v0").judge({}, counts)
    assert score == 1.0 and passed


@pytest.mark.slow
@pytest.mark.parametrize(
    "task", ["simlab/Stack-Cube-Franka-IK-Abs-v0", "simlab/Stack-Cube-Instance-Randomize-Franka-IK-Rel-v0"]
)
def test_the_scripted_stacking_state_machine_passes_the_criterion(task):
    """scripts/environments/state_machine/stack_cube_sm.py stacks all three cubes (8 envs, one or more episodes
    each: about 8 s of CPU), the subtask signals of env 0 turning true in Isaac Lab's order; on the IK-Rel
    task through its aims turned into clipped delta poses."""
    script = load_script(Path(__file__).parents[1] / "scripts/environments/state_machine/stack_cube_sm.py", "stack_sm")
    try:
        env = make(task, num_envs=8).unwrapped
        env.reset()
        first_true, step = {}, iter(range(10**6))

        def watch(obs):
            now = next(step)
            for name in SUBTASKS:
                if bool(obs["subtask_terms"][name][0]):
                    first_true.setdefault(name, now)

        _, counts = script.run(env, 200, watch, task=task)
        env.close()
    finally:
        sys.modules.pop("stack_sm", None)
    assert counts["episodes"] >= 8  # as many as the envs at least (a quick env starts another)
    assert criterion_for(task).judge({}, counts) == (1.0, True)
    assert first_true["grasp_1"] < first_true["stack_1"] < first_true["grasp_2"], first_true
