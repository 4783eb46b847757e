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


def test_two_image_history_reaches_rl_games_as_channels_and_plays_as_the_player_acts(tmp_path):
    """rl_games' CNN takes one (H, W, C) image: a history of two depth images is one image of two
    channels, oldest first (as rsl_rl's wrapper stacks it), in training and in play's policy."""
    from simlab.cli.libraries.rl_games import _runner, load_policy
    from simlab.tasks.utils import load_cfg_from_registry

    env = two_image_env()
    try:
        agent_cfg = load_cfg_from_registry("simlab/Cartpole-Depth-v0", "rl_games_cfg_entry_point")
        agent_cfg["params"]["config"].update(device="cpu", device_name="cpu")
        runner, wrapped = _runner(env, agent_cfg)
        assert wrapped.observation_space.shape == (100, 100, 2)
        for _ in range(2):  # two different images in the history
            stacked, *_ = wrapped.step(torch.ones(2, 1))
        raw = env.obs_buf["policy"]  # (N, 2, H, W, 1), as the env gives it
        assert stacked.shape == (2, 100, 100, 2) and not torch.equal(raw[:, 0], raw[:, 1])
        clip = agent_cfg["params"]["env"]["clip_observations"]
        for k in range(2):
            torch.testing.assert_close(stacked[..., k], raw[:, k, ..., 0].clamp(-clip, clip), rtol=0, atol=0)
        runner.params["config"].update(env_info=wrapped.get_env_info(), vec_env=wrapped)
        torch.manual_seed(0)
        player = runner.create_player()
        player.has_batch_dimension = True  # what its own env loop finds out from the first observation
        path = str(tmp_path / "cartpole.pth")
        torch.save({"model": player.model.state_dict()}, path)  # rl_games' checkpoint layout
        policy = load_policy(env, agent_cfg, path)
        with torch.no_grad():
            expected = player.get_action(stacked, is_deterministic=True)
            torch.testing.assert_close(policy({"policy": raw}), expected)
            swapped = policy({"policy": raw.flip(1)})  # the newest image first: another action
        assert not torch.allclose(swapped, expected)
    finally:
        env.close()


def test_skrl_refuses_an_image_history_in_one_line(tmp_path, capsys):
    """skrl's image models take one (H, W, C) image: a history is refused before training, naming the setting."""
    from simlab.cli.main import main

    argv = ["train", "--task", "simlab/Cartpole-Depth-v0", "--library", "skrl", "--num_envs", "2", "--device", "cpu"]
    argv += ["--headless", "--max_iterations", "1", "--log_root", str(tmp_path / "logs")]
    argv += [
        "env.observations.policy.image.history_length=2",
        "env.observations.policy.image.flatten_history_dim=false",
    ]
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()[-1]  # after skrl's own log lines
    assert err == (
        "simlab train: error: skrl takes one image per observation, but term 'policy/image' gives the last 2"
        " images (2, 100, 100, 1) (history_length=2, flatten_history_dim=False): train with rsl_rl or"
        " rl_games, which stack them along the channels, or set history_length=0."
    ), err


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
