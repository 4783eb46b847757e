"""The default (world-frame) video camera frames what an env is about: its robots and the objects near
them, not bodies kept far off; and it stands still once aimed."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import torch

import simlab.tasks  # noqa: F401 - registers the tasks
from simlab.envs.utils.viewer import view_frame
from simlab.tasks.utils import load_cfg_from_registry


def _make(task: str):
    cfg = load_cfg_from_registry(task, "env_cfg_entry_point")
    cfg.scene.num_envs = 1
    cfg.sim.device = "cpu"
    cfg.seed = 0
    env = gym.make(task, cfg=cfg)
    env.reset(seed=0)
    return env


def test_randomized_stack_frames_the_table_not_the_parked_cubes():
    """The unused cube instances are parked at (10, 10, 10) and fall from there after each reset."""
    env = _make("simlab/Stack-Cube-Instance-Randomize-Franka-IK-Rel-v0")
    try:
        u = env.unwrapped
        first = view_frame(u, u.cfg.viewer)
        for _ in range(20):  # the parked cubes fall about 2 m
            env.step(torch.zeros(env.action_space.shape))
        later = view_frame(u, u.cfg.viewer)
    finally:
        env.close()
    # the robot stands at the env origin on the table, its cubes at about x = 0.5
    assert np.linalg.norm(first.lookat[:2]) < 0.6 and -0.2 < first.lookat[2] < 0.8, first.lookat
    assert np.linalg.norm(first.eye - first.lookat) < 2.5
    np.testing.assert_array_equal(later.lookat, first.lookat)  # the camera does not chase what falls
    np.testing.assert_array_equal(later.eye, first.eye)


def test_a_far_object_does_not_pull_the_camera_and_a_near_one_does():
    env = _make("simlab/Lift-Cube-Franka-v0")
    try:
        u = env.unwrapped
        cube = u.scene["object"]

        def aim_with_cube_at(pos):
            pose = torch.tensor([[*pos, 1.0, 0.0, 0.0, 0.0]])
            cube.write_root_pose_to_sim(pose)
            u.sim.forward()
            u._view_aim = None  # aim afresh in this state
            return view_frame(u, u.cfg.viewer).lookat

        inside = aim_with_cube_at((0.2, 0.0, 0.3))  # within the arm's box: the arm's aim
        far = aim_with_cube_at((20.0, 20.0, 5.0))
        beside = aim_with_cube_at((0.5, 0.45, 0.03))  # beside the arm's box, near it
    finally:
        env.close()
    np.testing.assert_allclose(far, inside, atol=1e-9)
    assert beside[1] > inside[1] + 0.1, (beside, inside)
