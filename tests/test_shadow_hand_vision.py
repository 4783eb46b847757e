"""Shadow Hand cube reorientation from a camera (``simlab/Repose-Cube-Shadow-Vision-Direct-v0`` and its
-Play variant, Isaac Lab's vision task): it builds and steps on the CPU with Isaac Lab's 191-value policy
observation and 214-value critic state; the camera sees the cube (its segmentation mask); the CNN
beside the policy learns the cube's keypoints from the images within a few steps and writes a checkpoint;
the Play variant loads the newest checkpoint and does not train; the agent configs are Isaac Lab's."""

from __future__ import annotations

import math
import pathlib

import gymnasium as gym
import pytest
import torch

import simlab.tasks  # noqa: F401 - registers the tasks
from simlab.tasks.direct.shadow_hand.feature_extractor import (
    FeatureExtractor,
    FeatureExtractorCfg,
    FeatureExtractorNetwork,
)
from simlab.tasks.direct.shadow_hand.shadow_hand_vision_env import HIDDEN_GOAL_POS, compute_keypoints
from simlab.tasks.utils.criteria import criterion_for
from simlab.tasks.utils.parse_cfg import load_cfg_from_registry, parse_env_cfg
from simlab.utils.errors import CheckpointError, ConfigError
from simlab.utils.math import quat_from_angle_axis

TASK = "simlab/Repose-Cube-Shadow-Vision-Direct-v0"
PLAY = "simlab/Repose-Cube-Shadow-Vision-Direct-Play-v0"


def make(task: str, log_dir, num_envs: int = 2):
    cfg = parse_env_cfg(task, device="cpu", num_envs=num_envs)
    cfg.seed = 0
    cfg.feature_extractor.log_dir = str(log_dir)
    return gym.make(task, cfg=cfg).unwrapped


@pytest.fixture(scope="module")
def trained(tmp_path_factory):
    """The vision env after 12 steps of still actions (the CNN trained once per step), its losses."""
    log_dir = tmp_path_factory.mktemp("cnn")
    env = make(TASK, log_dir)
    obs, _ = env.reset(seed=0)
    losses, steps = [], []
    for _ in range(12):
        obs, reward, terminated, truncated, extras = env.step(torch.zeros(2, 20))
        losses.append(float(extras["log"]["pose_loss"]))
        steps.append((obs, reward))
    yield env, steps, losses, log_dir
    env.close()


def test_spaces_and_finite_steps_with_isaac_labs_sizes(trained):
    env, steps, _, _ = trained
    assert env.single_observation_space["policy"].shape == (191,)
    assert env.single_observation_space["critic"].shape == (214,)
    assert env.single_action_space.shape == (20,)
    for obs, reward in steps:
        assert obs["policy"].shape == (2, 191) and obs["critic"].shape == (2, 214)
        assert torch.isfinite(obs["policy"]).all() and torch.isfinite(obs["critic"]).all()
        assert torch.isfinite(reward).all()
    obs, _ = steps[-1]
    # the policy sees no cube state: its last 51 values are the CNN's 27 features and the goal's corners
    assert torch.equal(obs["policy"][:, 140:167], env.embeddings)
    assert torch.equal(obs["critic"][:, -27:], env.embeddings)
    goal = compute_keypoints(torch.cat((torch.zeros(2, 3), env.goal_rot), dim=-1))
    assert torch.allclose(obs["policy"][:, 167:], goal.view(2, 24))
    assert torch.allclose(env.goal_pos, torch.tensor(HIDDEN_GOAL_POS).expand(2, 3))
    assert env.graph_blockers() == ["the vision task trains its CNN inside the step (an optimizer step, checkpoints)"]


def test_the_camera_sees_the_cube_and_the_cnn_learns_its_keypoints(trained):
    env, _, losses, log_dir = trained
    output = env._tiled_camera.data.output
    assert output["rgb"].shape == (2, 120, 120, 3) and output["depth"].shape == (2, 120, 120, 1)
    cube_pixels = (env._segmentation_rgb()[..., 0] == 255).sum(dim=(1, 2))
    assert (cube_pixels > 200).all(), cube_pixels  # a 6 cm cube 0.4 m below the camera: hundreds of pixels
    # the camera looks straight down from 1 m: the cube's pixels lie within half its diagonal of its centre
    mask = env._segmentation_rgb()[..., 0] == 255
    half_diagonal = 0.03 * math.sqrt(3)
    for e in range(2):
        heights = 1.0 - output["depth"][e, ..., 0][mask[e]]
        assert (heights - env.object_pos[e, 2]).abs().max() < half_diagonal, e
    assert losses[-1] < 0.2 * losses[0], losses  # the regression trains beside the policy
    checkpoints = list(log_dir.glob("cnn_0_*.pth"))  # written at step 0, as Isaac Lab's
    assert len(checkpoints) == 1


def test_keypoints_are_the_cubes_corners():
    turn = quat_from_angle_axis(torch.tensor([math.pi / 2]), torch.tensor([[0.0, 0.0, 1.0]]))
    pose = torch.cat((torch.tensor([[0.1, 0.2, 0.3]]), turn), dim=-1)
    corners = compute_keypoints(pose)[0]
    assert torch.allclose(corners[0], torch.tensor([0.1 - 0.03, 0.2 + 0.03, 0.33]), atol=1e-6)  # (+,+,+) turned 90°
    assert torch.allclose(corners.mean(dim=0), pose[0, :3], atol=1e-6)
    assert torch.allclose((corners - pose[0, :3]).abs(), torch.full((8, 3), 0.03), atol=1e-6)


def test_play_loads_the_newest_checkpoint_and_does_not_train(trained, tmp_path):
    _, _, _, log_dir = trained
    with pytest.raises(ConfigError, match=r"holds no CNN checkpoint.*env\.feature_extractor\.log_dir=<folder>"):
        make(PLAY, tmp_path)
    env = make(PLAY, log_dir)
    saved = torch.load(next(log_dir.glob("*.pth")), weights_only=True)
    weights = env.feature_extractor.feature_extractor.state_dict()
    assert all(torch.equal(weights[name], saved[name]) for name in saved)
    obs, _ = env.reset(seed=0)
    _, _, _, _, extras = env.step(torch.zeros(2, 20))
    assert "pose_loss" not in extras["log"] and env.graph_blockers() == []
    assert all(torch.equal(env.feature_extractor.feature_extractor.state_dict()[name], saved[name]) for name in saved)
    assert env.cfg.scene.num_envs == 2  # the test's; the Play config's own is 64
    env.close()


class _TouchOnLoad:
    """A crafted checkpoint: unpickling it calls Path.touch on the marker (any call would do)."""

    def __init__(self, marker):
        self.marker = marker

    def __reduce__(self):
        return (pathlib.Path.touch, (pathlib.Path(self.marker),))


@pytest.mark.parametrize("content", ["crafted", "corrupt", "other_weights"])
def test_a_cnn_checkpoint_that_is_not_the_cnns_weights_is_refused_in_one_line(tmp_path, content):
    """Play reads the newest *.pth as data: a crafted pickle runs nothing (the marker never appears) and,
    like a corrupt file or another network's weights, is refused in one line naming the file."""
    marker = tmp_path / "pwned"
    path = tmp_path / "cnn_0_1.0.pth"
    if content == "crafted":
        torch.save({"cnn.0.weight": _TouchOnLoad(str(marker))}, path)
    elif content == "corrupt":
        torch.save(FeatureExtractorNetwork().state_dict(), path)
        path.write_bytes(path.read_bytes()[:-200])
    else:
        torch.save({"weight": torch.zeros(3)}, path)
    cfg = FeatureExtractorCfg(train=False, load_checkpoint=True, log_dir=str(tmp_path))
    with pytest.raises(CheckpointError) as error:
        FeatureExtractor(cfg, "cpu")
    message = str(error.value)
    assert "\n" not in message and f"'{path}'" in message and "allowed:" in message, message
    assert ("Refused" in message) == (content == "crafted"), message
    assert not marker.exists()


def test_agent_configs_and_criterion_follow_isaac_lab():
    for task in (TASK, PLAY):
        rsl = load_cfg_from_registry(task, "rsl_rl_cfg_entry_point")
        assert rsl.num_steps_per_env == 64 and rsl.actor.hidden_dims == [1024, 512, 512, 256, 128]
        assert rsl.algorithm.desired_kl == 0.01 and rsl.experiment_name == "shadow_hand_vision"
        games = load_cfg_from_registry(task, "rl_games_cfg_entry_point")["params"]
        assert games["network"]["mlp"]["units"] == [1024, 512, 512, 256, 128]
        assert games["config"]["horizon_length"] == 64 and games["config"]["minibatch_size"] == 19600
        assert criterion_for(task).description


@pytest.mark.slow
@pytest.mark.parametrize("library", ["rsl_rl", "rl_games"])
def test_one_training_iteration_writes_the_policy_and_the_cnn(tmp_path, monkeypatch, library):
    """`simlab train` with each of Isaac Lab's agents (the critic on the 214-value state): rsl_rl took
    15 s and rl_games 48 s on the 2-core CPU (2 envs, 64 steps an iteration)."""
    from simlab.cli.main import main

    monkeypatch.chdir(tmp_path)  # the CNN's checkpoints go to ./logs/shadow_hand_vision_cnn
    argv = ["train", "--task", TASK, "--library", library, "--num_envs", "2", "--device", "cpu", "--headless"]
    argv += ["--max_iterations", "1", "--log_root", str(tmp_path / "logs")]
    small = ["agent.params.config.minibatch_size=32", "agent.params.config.central_value_config.minibatch_size=64"]
    assert main(argv + (small if library == "rl_games" else [])) == 0
    assert list((tmp_path / "logs" / library).glob("*/*/"))
    assert list((tmp_path / "logs" / "shadow_hand_vision_cnn").glob("cnn_0_*.pth"))
