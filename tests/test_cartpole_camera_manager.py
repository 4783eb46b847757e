"""The manager-based camera cartpole configs (Isaac Lab's ``cartpole_camera_env_cfg``) and the
observation space of a non-concatenated group, bounded by its terms' clip ranges.

Oracle for depth: the pinhole model. The camera sits 3 m above the ground, pitched 12 degrees down;
below the cart, a pixel's ray meets the ground plane at 3 / (the ray's downward component).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import torch
from conftest import rendering_available

from simlab.envs import ManagerBasedRLEnv
from simlab.tasks.manager_based.classic.cartpole.cartpole_camera_env_cfg import (
    CartpoleDepthCameraEnvCfg,
    CartpoleRGBCameraEnvCfg,
)

pytestmark = pytest.mark.skipif(not rendering_available(), reason="no OpenGL context for the cameras")


def make_env(cfg_class, **observation_changes) -> ManagerBasedRLEnv:
    cfg = cfg_class()
    cfg.scene.num_envs = 2
    cfg.sim.device = "cpu"
    for key, value in observation_changes.items():
        setattr(cfg.observations.policy, key, value)
    return ManagerBasedRLEnv(cfg=cfg)


def ground_distance(row: int, col: int, size: int = 100, aperture: float = 20.955, focal: float = 24.0) -> float:
    """Distance from the camera to the ground along the ray through pixel (row, col)."""
    pitch = 2 * math.atan2(0.1045, 0.9945)  # the config's quaternion (w, 0, y, 0): 12 degrees nose down
    up = -(row + 0.5 - size / 2) * aperture / size / focal  # image rows run downwards
    left = -(col + 0.5 - size / 2) * aperture / size / focal
    norm = math.sqrt(1 + up**2 + left**2)
    down = (math.sin(pitch) - up * math.cos(pitch)) / norm  # downward part of the unit ray, world frame
    return 3.0 / down


def test_depth_camera_sees_the_ground_where_the_pinhole_model_says():
    env = make_env(CartpoleDepthCameraEnvCfg)
    try:
        obs, _ = env.reset()
        image = obs["policy"]
        assert image.shape == (2, 100, 100, 1)
        for row, col in ((49, 49), (50, 50), (60, 30), (70, 80)):
            expected = ground_distance(row, col)
            assert float(image[0, row, col, 0]) == pytest.approx(expected, abs=0.02), (row, col)
        assert (image[:, :20] == 0).all()  # sky: nothing within 20 m, written as 0
    finally:
        env.close()


def test_rgb_observation_is_mean_free_and_clip_bounds_its_space():
    env = make_env(CartpoleRGBCameraEnvCfg, concatenate_terms=False)
    try:  # no clip: an unbounded space
        space = env.single_observation_space["policy"]["image"]
        assert np.all(space.low == -np.inf) and np.all(space.high == np.inf) and space.shape == (100, 100, 3)
        obs, _ = env.reset()
        image = obs["policy"]["image"]
        torch.testing.assert_close(image.mean(dim=(1, 2)), torch.zeros(2, 3), atol=1e-5, rtol=0)
        assert image.abs().max() > 0.05  # not a blank frame
    finally:
        env.close()
    cfg = CartpoleRGBCameraEnvCfg()
    cfg.scene.num_envs, cfg.sim.device = 2, "cpu"
    cfg.observations.policy.concatenate_terms = False
    cfg.observations.policy.image.clip = (-0.02, 0.02)
    env = ManagerBasedRLEnv(cfg=cfg)
    try:  # a clipped term: its space is the clip range, and the observations lie in it
        space = env.single_observation_space["policy"]["image"]
        assert np.all(space.low == -0.02) and np.all(space.high == 0.02)
        obs, _ = env.reset()
        image = obs["policy"]["image"]
        assert space.contains(image[0].numpy()) and (image.abs() == 0.02).any()  # the clip was reached
    finally:
        env.close()


def two_image_env() -> ManagerBasedRLEnv:
    """The depth cartpole whose policy sees the last two images."""
    cfg = CartpoleDepthCameraEnvCfg()
    cfg.scene.num_envs, cfg.sim.device, cfg.seed = 2, "cpu", 3
    cfg.observations.policy.image.history_length = 2
    cfg.observations.policy.image.flatten_history_dim = False
    return ManagerBasedRLEnv(cfg=cfg)


def test_two_image_history_renders_once_per_step_and_reaches_rsl_rl_as_channels():
    from simlab.rl.rsl_rl import RslRlVecEnvWrapper

    env = two_image_env()
    try:
        wrapped = RslRlVecEnvWrapper(env)
        camera = env.scene["tiled_camera"]
        first = wrapped.get_observations()["policy"]
        assert first.shape == (2, 2, 100, 100)  # (N, images x channels, H, W), as rsl_rl's CNNs take them
        assert torch.equal(first[:, 0], first[:, 1])  # a fresh history repeats its first image
        frames = int(camera.frame[0])
        obs, _, _, extras = wrapped.step(torch.ones(2, 1))
        assert int(camera.frame[0]) == frames + 1  # one render per step: no final observations
        assert "final_obs" not in extras
        images = obs["policy"]
        torch.testing.assert_close(images[:, 0], first[:, 1])  # the older image first
        newest = env.observation_manager.compute_group("policy", update_history=False)[:, -1, ..., 0]
        assert not torch.equal(images[:, 1], images[:, 0])  # the pushed cart moved
        # the newest image is the camera's depth now (the term's value, unchanged by the wrapper)
        torch.testing.assert_close(images[:, 1], newest)
    finally:
        env.close()


def test_a_two_image_policy_plays_as_it_acted_in_training(tmp_path):
    """play's rsl_rl policy (load_policy, the exported module's input) stacks the images as training did."""
    from simlab.cli.libraries.rsl_rl import load_policy, make_runner
    from simlab.tasks.direct.cartpole.agents.rsl_rl_camera_ppo_cfg import CartpoleCameraPPORunnerCfg

    env = two_image_env()
    try:
        agent_cfg = CartpoleCameraPPORunnerCfg()
        agent_cfg.device = "cpu"
        torch.manual_seed(0)
        runner = make_runner(env, agent_cfg, None)
        path = str(tmp_path / "model_0.pt")
        runner.save(path)
        policy = load_policy(env, agent_cfg, path)
        for _ in range(2):  # two different images in the history
            stacked, *_ = runner.env.step(torch.ones(2, 1))
        raw = env.obs_buf  # (N, 2, H, W, 1), as the env gives it
        assert raw["policy"].shape == (2, 2, 100, 100, 1)
        with torch.no_grad():
            expected = runner.alg.actor(stacked).clamp(-1.0, 1.0)
            torch.testing.assert_close(policy(raw), expected)
            swapped = policy({"policy": raw["policy"].flip(1)})  # the newest image first: another action
        assert not torch.allclose(swapped, expected)
    finally:
        env.close()


def test_two_image_history_on_the_mujoco_warp_backend(monkeypatch):
    """The GPU code path (MuJoCo Warp physics and ray tracer, on Warp's CPU device) of the env its
    policy is trained on: one render per step, the history's shape."""
    pytest.importorskip("mujoco_warp")
    import simlab.sim.simulation_context as simulation_context
    from simlab.sensors.camera.warp_renderer import WarpCameraRenderer
    from simlab.sim.backends.cuda import CudaBackend

    def warp_on_cpu(model, num_envs, device, **options):
        return CudaBackend(model, num_envs, device="cpu", nconmax=options.get("nconmax"), njmax=options.get("njmax"))

    monkeypatch.setattr(simulation_context, "make_backend", warp_on_cpu)
    env = two_image_env()
    try:
        camera = env.scene["tiled_camera"]
        assert isinstance(camera._renderer, WarpCameraRenderer)
        frames = int(camera.frame[0])
        for _ in range(2):
            obs, *_ = env.step(torch.ones(2, 1))
        assert obs["policy"].shape == (2, 2, 100, 100, 1) and int(camera.frame[0]) == frames + 2
        newest = obs["policy"][:, 1, ..., 0]
        for row, col in ((60, 30), (70, 80)):  # the ground where the pinhole model puts it, as on the CPU
            assert float(newest[0, row, col]) == pytest.approx(ground_distance(row, col), abs=0.02)
    finally:
        env.close()
