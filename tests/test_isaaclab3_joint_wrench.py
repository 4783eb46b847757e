"""Isaac Lab 3.0's JointWrenchSensor on simlab (issue 42.3): the wrench each body of an articulation
receives through its joint, as 2.x's ``body_incoming_joint_wrench_b``; Isaac Lab 3.0's manager-based ant
(tests/ported3/isaaclab3_ant, with its physics presets and the feet wrenches it observes) steps on it."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest
import torch

import simlab.sim as sim_utils
from simlab import scene as scene2
from simlab.robots import CARTPOLE_CFG
from simlab.sensors import JointWrenchSensor, JointWrenchSensorCfg
from simlab.utils import configclass
from simlab.utils.errors import ConfigError

PORTED3 = Path(__file__).parent / "ported3"
FEET = ["front_left_foot", "front_right_foot", "left_back_foot", "right_back_foot"]


@pytest.fixture
def ported3():
    sys.path.insert(0, str(PORTED3))
    yield
    sys.path.remove(str(PORTED3))
    for name in [m for m in sys.modules if m.split(".")[0].startswith("isaaclab3_")]:
        del sys.modules[name]


def test_the_sensor_reads_the_cartpole_poles_weight_through_its_joint():
    @configclass
    class SceneCfg(scene2.InteractiveSceneCfg):
        robot = CARTPOLE_CFG.replace(prim_path="{ENV_REGEX_NS}/Robot")
        wrench = JointWrenchSensorCfg(prim_path="{ENV_REGEX_NS}/Robot")

    sim = sim_utils.SimulationContext(sim_utils.SimulationCfg(device="cpu", dt=0.005))
    scene = scene2.InteractiveScene(SceneCfg(num_envs=2, env_spacing=3.0))
    sensor = scene.sensors["wrench"]
    assert sensor.data.force is None  # before the simulation starts, as 3.0's
    sim.reset()
    robot = scene["robot"]
    for _ in range(3):
        sim.step()
        scene.update(sim.get_physics_dt())
    assert sensor.body_names == robot.body_names
    wrench = robot.data.body_incoming_joint_wrench_b
    assert torch.equal(torch.cat((sensor.data.force, sensor.data.torque), -1), wrench)
    # the upright pole at rest hangs on its hinge: the force it receives is its weight, upward
    (pole,), _ = sensor.find_bodies("pole")
    mass = float(sim.model.body_mass[robot._body_ids[pole]])
    force_w = torch.tensor([0.0, 0.0, 9.81 * mass])
    from simlab.utils.math import quat_apply

    assert torch.allclose(quat_apply(robot.data.body_quat_w[:, pole], sensor.data.force[:, pole]), force_w, atol=0.02)


def test_a_sensor_outside_a_scene_finds_its_articulation_and_a_wrong_path_is_refused():
    from simlab.assets import Articulation

    sim = sim_utils.SimulationContext(sim_utils.SimulationCfg(device="cpu"))
    robot = Articulation(CARTPOLE_CFG.replace(prim_path="/World/envs/env_.*/Robot"))  # a direct env's way
    sensor = JointWrenchSensor(JointWrenchSensorCfg(prim_path="/World/envs/env_.*/Robot"))
    lost = JointWrenchSensor(JointWrenchSensorCfg(prim_path="{ENV_REGEX_NS}/Cart"))
    sim.reset()
    assert sensor.data.force.shape == (1, robot.num_bodies, 3)
    with pytest.raises(ConfigError, match=r"JointWrenchSensorCfg\('\{ENV_REGEX_NS\}/Cart'\): no articulation"):
        lost.data.force  # noqa: B018
    with pytest.raises(ConfigError, match="the one convention is 'incoming_joint_frame'"):
        JointWrenchSensor(JointWrenchSensorCfg(prim_path="{ENV_REGEX_NS}/Robot", convention="world"))


def test_the_3_0_ant_manager_config_steps_with_its_joint_wrench_sensor(ported3):
    from isaaclab3_ant.ant_manager_env_cfg import AntEnvCfg

    import simlab.v3.envs as envs3

    cfg = AntEnvCfg()
    cfg.scene.num_envs, cfg.sim.device = 3, "cpu"
    env = envs3.ManagerBasedRLEnv(cfg)
    try:
        # the default physics preset, 3.0's MuJoCo Warp settings, set MuJoCo's options
        assert (env.sim.cfg.mujoco.njmax, env.sim.cfg.mujoco.nconmax, env.sim.cfg.mujoco.integrator) == (
            45,
            25,
            "implicitfast",
        )
        obs, _ = env.reset(seed=0)
        assert obs["policy"].shape == (3, 60)  # 3.0's ant observation size
        for _ in range(10):
            obs, reward, terminated, truncated, extras = env.step(torch.rand(3, 8) * 2 - 1)
        assert torch.isfinite(obs["policy"]).all() and torch.isfinite(reward).all()
        sensor = env.scene.sensors["joint_wrench"]
        ids, _ = sensor.find_bodies(FEET, preserve_order=True)
        feet = env.scene["robot"].data.body_incoming_joint_wrench_b[:, ids].reshape(3, -1)
        # the policy's feet wrenches (scale 0.1) are the sensor's, 3.0's .torch access included
        assert torch.allclose(obs["policy"][:, 28:52], 0.1 * feet)
        assert torch.equal(sensor.data.force.torch[:, ids], feet.view(3, 4, 6)[..., :3])
        (torso,), _ = sensor.find_bodies("torso")
        assert torch.allclose(sensor.data.force.torch[:, torso], torch.zeros(3, 3), atol=1e-4)  # a free base: nothing
    finally:
        env.close()


@pytest.mark.parametrize("physics", [None, "mujoco"])
def test_the_3_0_humanoid_manager_config_steps_with_either_physics_choice(ported3, physics):
    """Isaac Lab 3.0's humanoid: by default its PhysX preset (held; simlab's MuJoCo options), with
    ``physics=mujoco`` its ``newton_mjwarp`` preset (2 substeps of sim.dt / 2, njmax 80); both step."""
    from isaaclab3_humanoid.humanoid_manager_env_cfg import HumanoidEnvCfg

    import simlab.v3.envs as envs3
    from simlab.tasks.utils.presets import select_presets

    cfg = HumanoidEnvCfg()
    cfg.scene.num_envs, cfg.sim.device = 2, "cpu"
    cfg, _, _ = select_presets(cfg, None, [], physics)
    env = envs3.ManagerBasedRLEnv(cfg)
    try:
        substeps = 1 if physics is None else 2
        assert env.sim.model.opt.timestep == pytest.approx(cfg.sim.dt / substeps)
        assert env.scene["robot"].actuators["body"].cfg.armature == {".*": 0.01}  # the armature preset's default
        obs, _ = env.reset(seed=0)
        for _ in range(5):
            obs, reward, *_ = env.step(torch.rand(2, 21) * 2 - 1)
        assert obs["policy"].shape == (2, 87) and torch.isfinite(obs["policy"]).all()
        ids, _ = env.scene.sensors["joint_wrench"].find_bodies(["left_foot", "right_foot"])
        feet = env.scene["robot"].data.body_incoming_joint_wrench_b[:, ids].reshape(2, -1)
        assert torch.allclose(obs["policy"][:, 54:66], 0.01 * feet)
    finally:
        env.close()
