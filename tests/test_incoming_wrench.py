"""Isaac Lab's ``mdp.body_incoming_wrench`` / ``ArticulationData.body_incoming_joint_wrench_b``: the wrench
each body receives from its parent through its joint, from MuJoCo's ``cfrc_int``, checked against
MuJoCo's own force and torque sensors on a site at each body's origin (the gravity-compensated case:
tests/test_shadow_openai.py)."""

from __future__ import annotations

import mujoco
import pytest
import torch

import simlab.sim as sim_utils
from simlab.assets import AssetBaseCfg
from simlab.envs import ManagerBasedRLEnv, mdp
from simlab.managers import ObservationTermCfg as ObsTerm
from simlab.managers import SceneEntityCfg
from simlab.robots.ant import ANT_CFG
from simlab.scene import InteractiveScene, InteractiveSceneCfg
from simlab.utils import configclass
from simlab.utils.errors import ConfigError

FEET = ["front_left_foot", "front_right_foot", "left_back_foot", "right_back_foot"]


@configclass
class AntSceneCfg(InteractiveSceneCfg):
    ground = AssetBaseCfg(prim_path="/World/ground", spawn=sim_utils.GroundPlaneCfg())
    robot = ANT_CFG.replace(prim_path="{ENV_REGEX_NS}/Robot")


def _force_torque_sensors(sim, bodies: list[str]):
    """MuJoCo's force and torque sensors on a site at each body's origin (added before the model compiles):
    the interaction with the parent in the body's frame. ``read()`` -> (num_envs, bodies, 6)."""
    for body in bodies:
        sim.spec.body(body).add_site(name=f"{body}/ft", group=5)
        for kind, sensor in (("force", mujoco.mjtSensor.mjSENS_FORCE), ("torque", mujoco.mjtSensor.mjSENS_TORQUE)):
            sim.spec.add_sensor(
                name=f"{body}/{kind}", type=sensor, objtype=mujoco.mjtObj.mjOBJ_SITE, objname=f"{body}/ft"
            )

    def read() -> torch.Tensor:
        sim.physics.ensure_forward()
        data = sim.physics.data("sensordata")
        cols = [
            int(sim.model.sensor(f"{b}/{k}").adr[0]) + i for b in bodies for k in ("force", "torque") for i in range(3)
        ]
        return data[:, cols].reshape(data.shape[0], len(bodies), 6)

    return read


def test_incoming_wrench_matches_mujocos_force_and_torque_sensors():
    sim = sim_utils.SimulationContext(sim_utils.SimulationCfg(dt=1 / 120, device="cpu"))
    scene = InteractiveScene(AntSceneCfg(num_envs=3, env_spacing=3.0))
    bodies = ["torso", "front_left_leg", *FEET]
    sensors = _force_torque_sensors(sim, [f"Robot/{b}" for b in bodies])  # they run the post-constraint pass
    sim.reset()
    robot = scene["robot"]
    generator = torch.Generator().manual_seed(0)
    for _ in range(60):  # falling, landing on the feet, pushed by random joint efforts
        robot.set_joint_effort_target(torch.rand(3, robot.num_joints, generator=generator) * 2 - 1)
        scene.write_data_to_sim()
        sim.step()
        scene.update(sim.get_physics_dt())
    ids = [robot.body_names.index(b) for b in bodies]
    reference = sensors()  # the sensors of the last forward pass
    ours = robot.data.body_incoming_joint_wrench_b[:, ids]  # cfrc_int of the same pass
    assert reference[:, 2:].abs().amax() > 1.0  # the feet carry the ant: a check with something in it
    torch.testing.assert_close(ours, reference, atol=1e-3, rtol=1e-3)
    # the torso is the root: its free joint transmits nothing from the world
    assert ours[:, 0].abs().amax() < 1e-3


def test_without_the_post_constraint_pass_it_says_how_to_get_it():
    sim = sim_utils.SimulationContext(sim_utils.SimulationCfg(dt=1 / 120, device="cpu"))
    scene = InteractiveScene(AntSceneCfg(num_envs=1, env_spacing=3.0))
    sim.reset()
    with pytest.raises(ConfigError, match="mdp.body_incoming_wrench"):
        _ = scene["robot"].data.body_incoming_joint_wrench_b


def test_isaaclab_ant_observation_term_runs_in_the_manager_based_env():
    """Isaac Lab's manager-based ant observes ``feet_body_forces`` (scale 0.1): the env turns the pass on."""
    from simlab.tasks.manager_based.classic.ant.ant_env_cfg import AntEnvCfg

    cfg = AntEnvCfg()
    cfg.scene.num_envs = 2
    cfg.sim.device = "cpu"
    cfg.observations.policy.feet_body_forces = ObsTerm(
        func=mdp.body_incoming_wrench, scale=0.1, params={"asset_cfg": SceneEntityCfg("robot", body_names=FEET)}
    )
    env = ManagerBasedRLEnv(cfg)
    try:
        obs, _ = env.reset()
        for _ in range(30):
            obs, *_ = env.step(torch.zeros(2, env.action_manager.total_action_dim))
        feet = obs["policy"][:, -24:]  # the term added last
        robot = env.scene["robot"]
        ids = robot.find_bodies(FEET, preserve_order=True)[0]
        expected = 0.1 * robot.data.body_incoming_joint_wrench_b[:, ids].reshape(2, -1)
        torch.testing.assert_close(feet, expected)
        assert feet.abs().amax() > 0.05
    finally:
        env.close()
