"""Isaac Lab's ``mdp.image_features`` on the manager-based camera cartpole: simlab's frozen seeded CNN,
a user's model zoo entry, and one-line refusals for models simlab cannot run here."""

from __future__ import annotations

import importlib.util

import pytest
import torch
from conftest import rendering_available

from simlab.envs import ManagerBasedRLEnv, mdp
from simlab.managers import ObservationTermCfg as ObsTerm
from simlab.managers import SceneEntityCfg
from simlab.tasks.manager_based.classic.cartpole.cartpole_camera_env_cfg import CartpoleRGBCameraEnvCfg
from simlab.utils.errors import ConfigError

pytestmark = pytest.mark.skipif(not rendering_available(), reason="no OpenGL context for the cameras")


def _env(**params) -> ManagerBasedRLEnv:
    cfg = CartpoleRGBCameraEnvCfg()
    cfg.scene.num_envs = 2
    cfg.sim.device = "cpu"
    cfg.seed = 0
    params = {"sensor_cfg": SceneEntityCfg("tiled_camera"), "data_type": "rgb", **params}
    cfg.observations.policy.image = ObsTerm(func=mdp.image_features, params=params)
    return ManagerBasedRLEnv(cfg=cfg)


def test_simlab_cnn_features_are_seeded_and_follow_the_image():
    features = []
    for _ in range(2):
        env = _env(model_name="simlab-cnn-random")
        try:
            obs, _ = env.reset()
            features.append(obs["policy"])
            for _ in range(20):  # pushed: the carts move across the image
                moved = env.step(torch.ones(2, 1))[0]["policy"]
        finally:
            env.close()
    assert features[0].shape == (2, 64)
    torch.testing.assert_close(features[0], features[1])  # the same weights in every run
    assert (moved - features[0]).abs().amax() > 1e-3


def test_a_model_zoo_entry_is_used_as_in_isaac_lab():
    zoo = {"mean-colour": {"model": lambda: None, "inference": lambda model, images: images.mean(dim=(1, 2))}}
    env = _env(model_name="mean-colour", model_zoo_cfg=zoo)
    try:
        obs, _ = env.reset()
        images = env.scene["tiled_camera"].data.output["rgb"].float()
        torch.testing.assert_close(obs["policy"], images.mean(dim=(1, 2)))
    finally:
        env.close()


@pytest.mark.parametrize(
    ("model_name", "said"),
    [("theia-tiny-patch16-224-cddsv", "Theia model"), ("vit-huge", "unknown model_name"), ("resnet18", "torchvision")],
)
def test_models_simlab_cannot_run_are_refused_in_one_line(model_name, said):
    if model_name == "resnet18" and importlib.util.find_spec("torchvision") is not None:
        pytest.skip("torchvision is installed: the ResNet runs")
    with pytest.raises(ConfigError, match=said) as err:
        _env(model_name=model_name)
    assert "\n" not in str(err.value) and "simlab-cnn-random" in str(err.value)
