"""The default (world-frame) video camera frames what an env is about: its robots and the objects near
them, not bodies kept far off; once aimed, it moves only with the robots' roots (a running robot stays
in the picture, a fixed-base arm's camera stands still)."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest
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


def _in_picture(u, frame, points: np.ndarray) -> np.ndarray:
    """Where ``points`` (reference frame) land in ``frame``'s picture: (x, y) in [-1, 1] inside it."""
    forward = (frame.lookat - frame.eye) / np.linalg.norm(frame.lookat - frame.eye)
    right = np.cross(forward, [0.0, 0.0, 1.0])
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    rel = points - frame.eye
    depth = rel @ forward
    assert (depth > 0).all(), "behind the camera"
    width, height = u.cfg.viewer.resolution
    tan_y = np.tan(np.radians(u.sim.model.vis.global_.fovy) / 2)
    return np.stack([rel @ right / depth / (tan_y * width / height), rel @ up / depth / tan_y], axis=-1)


def _robot_geoms(u) -> np.ndarray:
    model = u.sim.model
    return np.flatnonzero(np.isin(model.geom_bodyid, u.scene["robot"]._body_ids) & (model.geom_rgba[:, 3] > 0))


def test_a_running_robot_stays_in_the_picture():
    """The humanoid's root carried 20 m across the floor, 5 cm a frame, then teleported 30 m: the camera
    follows without jumps and keeps every one of its geoms in the picture (the aim held from the first
    frame loses it after a metre or two)."""
    env = _make("simlab/Humanoid-v0")
    try:
        u = env.unwrapped
        robot = u.scene["robot"]
        start = robot.data.root_state_w[:, :7].clone()
        geoms = _robot_geoms(u)
        first = view_frame(u, u.cfg.viewer)
        path = [np.array([0.05 * i, 0.03 * i, 0.0]) for i in range(401)] + [np.array([-30.0, 10.0, 0.0])]
        previous = first
        for step, offset in enumerate(path):
            pose = start.clone()
            pose[:, :3] += torch.as_tensor(offset, dtype=pose.dtype)
            robot.write_root_pose_to_sim(pose)
            u.sim.forward()
            frame = view_frame(u, u.cfg.viewer)
            xpos = u.sim.physics.data("geom_xpos")[0].numpy().astype(np.float64)[geoms]
            assert (np.abs(_in_picture(u, frame, xpos)) < 0.9).all(), f"out of the picture at {offset}"
            if step < len(path) - 1:  # no jumps: the camera moves no more than the robot did
                assert np.linalg.norm(frame.lookat - previous.lookat) <= 0.0584 + 1e-9
            np.testing.assert_allclose(frame.eye - frame.lookat, first.eye - first.lookat, atol=1e-9)
            previous = frame
    finally:
        env.close()
    assert np.linalg.norm(frame.lookat - first.lookat) > 25.0


@pytest.mark.parametrize(
    "task", ["simlab/Lift-Cube-Franka-v0", "simlab/Stack-Cube-Instance-Randomize-Franka-IK-Rel-v0"]
)
def test_a_fixed_base_arm_moving_leaves_the_camera_still(task):
    """The arm swings through its workspace (random actions) and the parked cubes fall: the camera
    of the first frame is kept, to the bit."""
    env = _make(task)
    try:
        u = env.unwrapped
        hand = u.scene["robot"].find_bodies("panda_hand")[0][0]
        first = view_frame(u, u.cfg.viewer)
        hand_start = u.scene["robot"].data.body_pos_w[0, hand].clone()
        generator = torch.Generator().manual_seed(0)
        travel = 0.0
        for _ in range(40):
            action = 2 * torch.rand(env.action_space.shape, generator=generator) - 1
            env.step(action)
            travel = max(travel, float(torch.linalg.norm(u.scene["robot"].data.body_pos_w[0, hand] - hand_start)))
            frame = view_frame(u, u.cfg.viewer)
            np.testing.assert_array_equal(frame.lookat, first.lookat)
            np.testing.assert_array_equal(frame.eye, first.eye)
    finally:
        env.close()
    assert travel > 0.1, f"the hand moved only {travel:.3f} m"


def test_a_camera_named_between_far_apart_envs_frames_the_reference_env():
    """The camera cartpoles stand 20 m apart and their viewer names the world point (0, 0, 2.5) from
    7 m: no env within the camera's reach of it (the 4 envs stand at (+-10, +-10)). The video shows
    env 0 from the configured direction and distance: its cart anywhere on the rail (up to the 3 m
    bound) and its pole lie in the picture, large enough to see (framed from the middle of all four,
    env 0 lay behind the camera)."""
    task = "simlab/Cartpole-Depth-v0"
    cfg = load_cfg_from_registry(task, "env_cfg_entry_point")
    cfg.scene.num_envs = 4
    cfg.sim.device = "cpu"
    cfg.seed = 0
    env = gym.make(task, cfg=cfg)
    try:
        u = env.unwrapped
        env.reset(seed=0)
        robot = u.scene["robot"]
        model = u.sim.model
        bodies = np.asarray(robot._body_ids)  # the MuJoCo body of each of the robot's bodies
        cart, pole = (
            int(np.flatnonzero(model.geom_bodyid == bodies[robot.find_bodies(n)[0][0]])[0]) for n in ("cart", "pole")
        )
        first = view_frame(u, u.cfg.viewer)
        configured = np.subtract(u.cfg.viewer.eye, u.cfg.viewer.lookat)
        for x in (-3.0, 0.0, 3.0):
            joints = torch.tensor([[x, 0.0]]).repeat(u.num_envs, 1)
            robot.write_joint_state_to_sim(joints, torch.zeros_like(joints))
            u.sim.forward()
            frame = view_frame(u, u.cfg.viewer)
            np.testing.assert_allclose(frame.eye - frame.lookat, configured, atol=1e-9)
            np.testing.assert_array_equal(frame.lookat, first.lookat)  # a fixed-base robot: no follow
            xpos = u.sim.physics.data("geom_xpos")[0].numpy().astype(np.float64)
            xmat = u.sim.physics.data("geom_xmat")[0].numpy().astype(np.float64).reshape(-1, 3, 3)
            half_pole = xmat[pole] @ [0.0, 0.0, model.geom_size[pole, 2]]
            points = np.stack([xpos[cart], xpos[pole] - half_pole, xpos[pole] + half_pole])
            seen = _in_picture(u, frame, points)
            assert (np.abs(seen) < 0.9).all(), f"env 0's cartpole out of the picture with the cart at {x} m: {seen}"
            assert np.ptp(seen[:, 1]) > 0.2, f"the pole spans only {np.ptp(seen[:, 1]) / 2:.0%} of the picture's height"
    finally:
        env.close()
