"""Franka cube stacking with a random pick of cubes per env (Isaac Lab's instance-randomized stack tasks):
each env holds every candidate cube and brings one of each set into focus, the others parked; the
observations, subtask signals and success read the cubes in focus; a reset re-picks only its envs."""

from __future__ import annotations

import gymnasium as gym
import pytest
import torch

import simlab.tasks  # noqa: F401 - registers the tasks
from simlab.tasks.manager_based.manipulation.stack.config.franka.stack_joint_pos_env_cfg import CUBE_SIZE
from simlab.tasks.manager_based.manipulation.stack.config.franka.stack_joint_pos_instance_randomize_env_cfg import (
    CANDIDATES,
)
from simlab.tasks.utils.criteria import criterion_for
from simlab.tasks.utils.parse_cfg import parse_env_cfg

TASKS = ["simlab/Stack-Cube-Instance-Randomize-Franka-v0", "simlab/Stack-Cube-Instance-Randomize-Franka-IK-Rel-v0"]
CUBES = ("cube_1", "cube_2", "cube_3")


def make(task: str, num_envs: int = 2, seed: int = 0):
    cfg = parse_env_cfg(task, device="cpu", num_envs=num_envs)
    cfg.seed = seed
    env = gym.make(task, cfg=cfg).unwrapped
    env.reset(seed=seed)
    return env


def focused_and_parked(env) -> tuple[torch.Tensor, torch.Tensor]:
    """(envs, 3 cubes, 3) env-frame positions of the picked candidates, and (envs, parked, 3) the others'."""
    picked, parked = [], []
    for k, name in enumerate(CUBES):
        positions = env.scene[name].data.object_pos_w - env.scene.env_origins[:, None]  # (envs, candidates, 3)
        chosen = env.rigid_objects_in_focus[:, k]
        in_focus = chosen[:, None] == torch.arange(positions.shape[1])
        picked.append(positions[in_focus])
        parked.append(positions[~in_focus].view(env.num_envs, -1, 3))
    return torch.stack(picked, dim=1), torch.cat(parked, dim=1)


@pytest.mark.parametrize("task", TASKS)
def test_task_builds_and_steps_with_one_candidate_of_each_cube_in_every_env(task):
    env = make(task)
    assert [env.scene[name].object_names for name in CUBES] == [list(c) for c in CANDIDATES.values()]
    obs = env.observation_manager.compute()
    assert obs["policy"]["object"].shape == (2, 39) and obs["policy"]["cube_positions"].shape == (2, 9)
    assert obs["policy"]["cube_orientations"].shape == (2, 12)
    assert env.rigid_objects_in_focus.shape == (2, 3)
    width = 7 if "IK-Rel" in task else 8
    for _ in range(5):
        obs, _, terminated, truncated, _ = env.step(torch.zeros(2, width))
    assert all(torch.isfinite(v).all() for v in obs["policy"].values())
    assert not any(obs["subtask_terms"][name].any() for name in ("grasp_1", "stack_1", "grasp_2"))
    assert not terminated.any() and not truncated.any()
    picked, parked = focused_and_parked(env)
    # the picked cubes rest on the table where the observations say; the others are far away
    assert torch.allclose(obs["policy"]["cube_positions"].view(2, 3, 3) - env.scene.env_origins[:, None], picked)
    assert (picked[..., 2] - CUBE_SIZE / 2).abs().max() < 0.002 and (picked[..., 0] > 0.35).all()
    assert (parked[..., :2] - env.scene.env_origins[:, None, :2] > 5.0).all()  # parked near world (10, 10)
    env.close()


def test_the_picks_differ_across_envs_follow_the_seed_and_a_reset_repicks_only_its_envs():
    env = make(TASKS[0], num_envs=16, seed=3)
    picks = env.rigid_objects_in_focus.clone()
    for k in range(3):  # both candidates of every cube occur across the 16 envs
        assert set(picks[:, k].tolist()) == {0, 1}
    again = make(TASKS[0], num_envs=16, seed=3)
    assert torch.equal(again.rigid_objects_in_focus, picks)
    again.close()
    actions = torch.zeros(16, 8)
    repicked = torch.zeros(16, dtype=torch.bool)
    for _ in range(4):
        before = env.rigid_objects_in_focus.clone()
        env.episode_length_buf[::2] = env.max_episode_length  # the even envs time out in this step
        env.step(actions)
        repicked |= (env.rigid_objects_in_focus != before).any(dim=1)
        assert torch.equal(env.rigid_objects_in_focus[1::2], before[1::2])
    assert repicked[::2].any() and not repicked[1::2].any()
    picked, _ = focused_and_parked(env)
    gaps = torch.cdist(picked[::2], picked[::2]) + torch.eye(3)
    assert (gaps > 0.1).all()  # the reset envs' picks placed 10 cm apart
    env.close()


def test_a_tower_of_the_cubes_in_focus_is_stacked_and_a_success_but_one_of_parked_cubes_is_not():
    env = make(TASKS[0])
    on_step, counts = criterion_for(TASKS[0]).make_hook()
    base = torch.tensor([0.5, 0.0, CUBE_SIZE / 2])
    for level, name in enumerate(CUBES):
        collection = env.scene[name]
        state = collection.data.object_state_w.clone()
        for e in range(2):
            # env 0: the candidates in focus form the tower; env 1: the parked ones do
            k = int(env.rigid_objects_in_focus[e, level])
            j = k if e == 0 else 1 - k
            state[e, j, :3] = base + env.scene.env_origins[e] + torch.tensor([0.0, 0.0, level * CUBE_SIZE])
            state[e, j, 3:7] = torch.tensor([1.0, 0.0, 0.0, 0.0])
            state[e, j, 7:] = 0.0
        collection.write_object_state_to_sim(state)
    env.scene.update(0.0)
    subtasks = env.observation_manager.compute()["subtask_terms"]
    assert subtasks["stack_1"].tolist() == [True, False]  # cube 2 on cube 1, gripper open
    actions = torch.zeros(2, 8)
    actions[:, -1] = 1.0  # open
    for _ in range(10):
        obs, _, terminated, _, _ = env.step(actions)
        on_step(env, obs, actions)
        if terminated.any():
            break
    assert terminated.tolist() == [True, False]
    assert counts == {"success": 1, "episodes": 1}
    env.close()
