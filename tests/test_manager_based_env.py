"""The base manager-based env (no rewards): construction order, stepping, resets, camera, close."""

from __future__ import annotations

import numpy as np
import pytest
import torch

import simlab.envs.mdp as mdp
from simlab.envs import ManagerBasedEnv, ManagerBasedEnvCfg
from simlab.managers import EventTermCfg as EventTerm
from simlab.managers import ObservationGroupCfg as ObsGroup
from simlab.managers import ObservationTermCfg as ObsTerm
from simlab.sim import SimulationContext
from simlab.tasks.manager_based.classic.cartpole.cartpole_env_cfg import CartpoleSceneCfg
from simlab.utils import configclass

N = 3


@configclass
class ActionsCfg:
    joint_effort = mdp.JointEffortActionCfg(asset_name="robot", joint_names=["slider_to_cart"], scale=5.0)


@configclass
class ObservationsCfg:
    @configclass
    class PolicyCfg(ObsGroup):
        joint_pos = ObsTerm(func=mdp.joint_pos_rel)
        joint_vel = ObsTerm(func=mdp.joint_vel_rel)

    policy: PolicyCfg = PolicyCfg()


def startup_mark(env, env_ids, value: float):
    env.startup_seen = (env_ids.tolist(), env.sim.backend is not None)


@configclass
class EventCfg:
    mark = EventTerm(func=startup_mark, mode="startup", params={"value": 1.0})
    reset_all = EventTerm(func=mdp.reset_scene_to_default, mode="reset")


@configclass
class CartpoleBaseEnvCfg(ManagerBasedEnvCfg):
    scene = CartpoleSceneCfg(num_envs=N, env_spacing=4.0)
    actions = ActionsCfg()
    observations = ObservationsCfg()
    events = EventCfg()

    def __post_init__(self):
        self.decimation = 4
        self.sim.dt = 0.005
        self.sim.device = "cpu"
        self.viewer.eye = (4.0, 0.0, 3.0)
        self.viewer.lookat = (0.0, 0.0, 2.0)


def test_construction_step_and_reset():
    env = ManagerBasedEnv(CartpoleBaseEnvCfg())
    assert env.startup_seen == ([0, 1, 2], True)  # startup events run once the simulation started
    assert env.num_envs == N and env.device == "cpu" and env.step_dt == pytest.approx(0.02)
    assert SimulationContext.instance() is env.sim
    assert env.sim.camera_eye == (4.0, 0.0, 3.0) and env.sim.camera_target == (0.0, 0.0, 2.0)
    obs, extras = env.reset()
    assert obs["policy"].shape == (N, 4)
    for _ in range(5):
        obs, extras = env.step(torch.ones(N, 1))
    assert env._sim_step_counter == 5 * 4
    assert (obs["policy"][:, 0] > 0).all()  # pushed along +y
    moved = env.scene["robot"].data.joint_pos.clone()
    obs, _ = env.reset(env_ids=[1])
    assert obs["policy"][1].abs().max() == 0  # back to the default state
    torch.testing.assert_close(env.scene["robot"].data.joint_pos[[0, 2]], moved[[0, 2]])
    env.close()
    assert SimulationContext.instance() is None


def test_a_second_env_replaces_the_first_simulation():
    first = ManagerBasedEnv(CartpoleBaseEnvCfg())
    second = ManagerBasedEnv(CartpoleBaseEnvCfg())
    assert SimulationContext.instance() is second.sim is not first.sim
    second.reset()
    second.step(torch.zeros(N, 1))
    first.close()
    assert SimulationContext.instance() is second.sim  # closing the old env leaves the new one alone
    second.close()


def test_camera_pose_by_origin_type():
    cfg = CartpoleBaseEnvCfg()
    cfg.viewer.env_index = 1
    env = ManagerBasedEnv(cfg)
    origin = env.scene.env_origins[1].numpy()
    eye, lookat = env._camera_pose()
    np.testing.assert_allclose(eye, np.array([4.0, 0.0, 3.0]) - origin, atol=1e-6)
    env.cfg.viewer.origin_type = "env"
    eye, lookat = env._camera_pose()
    np.testing.assert_allclose(lookat, [0.0, 0.0, 2.0])
    env.cfg.viewer.origin_type = "asset_root"
    env.cfg.viewer.asset_name = "robot"
    eye, lookat = env._camera_pose()
    np.testing.assert_allclose(lookat, [0.0, 0.0, 4.0], atol=1e-6)  # relative to the root, spawned at z = 2
    env.cfg.viewer.env_index = 7
    with pytest.raises(ValueError, match="env_index is 7, but there are 3 envs"):
        env._camera_pose()
    env.close()


def test_invalid_decimation_is_rejected():
    cfg = CartpoleBaseEnvCfg()
    cfg.decimation = 0
    with pytest.raises(ValueError, match="decimation must be an int >= 1"):
        ManagerBasedEnv(cfg)


@pytest.mark.parametrize("seconds", [0.0, -1.0])
def test_an_episode_that_is_not_positive_is_rejected(seconds):
    from simlab.envs import ManagerBasedRLEnv
    from simlab.tasks.manager_based.classic.cartpole.cartpole_env_cfg import CartpoleEnvCfg

    cfg = CartpoleEnvCfg()
    cfg.scene.num_envs, cfg.sim.device, cfg.episode_length_s = 2, "cpu", seconds
    with pytest.raises(ValueError, match="episode_length_s must be a positive number of seconds"):
        ManagerBasedRLEnv(cfg)
