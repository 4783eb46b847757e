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
from simlab.utils import configclass, versions

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


def _ant_after_random_efforts(device: str, compiled_in: bool, steps: int = 40) -> dict[str, torch.Tensor]:
    """Three ants pushed by random joint efforts, world 1 heavier (per-world masses, set_const): the
    incoming wrenches and MuJoCo's post-constraint fields at the end, with the state they belong to."""
    sim = sim_utils.SimulationContext(sim_utils.SimulationCfg(dt=1 / 120, device=device))
    scene = InteractiveScene(AntSceneCfg(num_envs=3, env_spacing=3.0))
    if compiled_in:
        sim_utils.compute_body_interaction_forces(sim.spec)
    sim.reset()
    robot = scene["robot"]
    masses = robot.root_physx_view.get_masses()
    masses[1] *= 1.5
    robot.root_physx_view.set_masses(masses, [1])
    generator = torch.Generator().manual_seed(0)
    for _ in range(steps):  # falling, landing on the feet
        efforts = torch.rand(3, robot.num_joints, generator=generator) * 2 - 1
        robot.set_joint_effort_target(efforts.to(sim.device))
        scene.write_data_to_sim()
        sim.step()
        scene.update(sim.get_physics_dt())
    read = {"wrench": robot.data.body_incoming_joint_wrench_b}
    read |= {name: sim.physics.post_constraint(name) for name in ("cacc", "cfrc_int", "cfrc_ext")}
    read["qpos"] = sim.physics.data("qpos")
    return {name: value.clone().cpu() for name, value in read.items()}


def test_without_the_pass_compiled_in_it_runs_when_read_with_the_compiled_in_values(monkeypatch):
    """Isaac Lab's task files read PhysX's incoming joint forces with nothing that turns MuJoCo's
    post-constraint pass on before the model compiles: the backend runs it when they are read. The
    same run with the pass compiled in and without: the same state, read both ways, the same values
    (MuJoCo's own computation both times, so exactly)."""
    compiled_in = _ant_after_random_efforts("cpu", compiled_in=True)
    sim_utils.SimulationContext.clear_instance()
    monkeypatch.setattr(versions, "_warned", set())  # the note is given once per process
    with pytest.warns(UserWarning, match="post-constraint pass"):  # a one-time note says what it costs
        on_demand = _ant_after_random_efforts("cpu", compiled_in=False)
    assert torch.equal(on_demand["qpos"], compiled_in["qpos"])  # the pass changes no trajectory
    assert compiled_in["cfrc_ext"][:, 2:].abs().amax() > 1.0  # the ants stand on their feet: contact forces
    for name in ("wrench", "cacc", "cfrc_int", "cfrc_ext"):
        assert torch.equal(on_demand[name], compiled_in[name]), name


def test_the_pass_run_when_read_follows_the_state():
    """Computed once per state: a step and a state write give new values, as the compiled-in pass."""
    sim = sim_utils.SimulationContext(sim_utils.SimulationCfg(dt=1 / 120, device="cpu"))
    scene = InteractiveScene(AntSceneCfg(num_envs=2, env_spacing=3.0))
    sim.reset()
    robot, physics = scene["robot"], sim.physics
    for _ in range(30):
        sim.step()
    first = physics.post_constraint("cfrc_int").clone()
    assert torch.equal(physics.post_constraint("cfrc_int"), first)  # the same state: not run again
    sim.step()
    assert not torch.equal(physics.post_constraint("cfrc_int"), first)
    pose = robot.data.root_state_w[:, :7].clone()
    pose[:, 2] += 1.0  # lifted off the ground: the feet carry nothing
    robot.write_root_pose_to_sim(pose)
    feet = [robot.body_names.index(b) for b in FEET]
    assert robot.data.body_incoming_joint_wrench_b[:, feet].abs().amax() < 1.0
    with pytest.raises(ValueError, match="cfrc_int"):
        physics.post_constraint("qfrc_constraint")


@pytest.mark.parametrize("edit", ["geom", "late_pass"])
def test_the_pass_run_when_read_refuses_a_spec_edited_after_the_model_compiled(edit):
    """The cpu backend runs the pass in the spec compiled again: a geom added to the spec after
    ``sim.reset()`` (which the simulation never sees) would be in that model's contacts, not in the
    simulated worlds'; the pass asked for too late (``compute_body_interaction_forces`` after
    ``sim.reset()``) would fail to compile on its sensor's name. It says what happened instead."""
    sim = sim_utils.SimulationContext(sim_utils.SimulationCfg(dt=1 / 120, device="cpu"))
    scene = InteractiveScene(AntSceneCfg(num_envs=1, env_spacing=3.0))
    sim.reset()
    if edit == "geom":
        sim.spec.worldbody.add_geom(type=mujoco.mjtGeom.mjGEOM_BOX, size=[0.5, 0.5, 0.5], pos=[0, 0, 0.5])
    else:
        sim_utils.compute_body_interaction_forces(sim.spec)
    with pytest.raises(RuntimeError, match=r"edited after sim.reset\(\)"):
        _ = scene["robot"].data.body_incoming_joint_wrench_b


@pytest.mark.gpu
def test_the_pass_run_when_read_on_the_gpu_gives_mujoco_warps_own():
    """MuJoCo Warp: the pass launched when read equals the one its forward runs with the pass on
    (``opt.run_rne_postconstraint``), at the same state; and it agrees with the compiled-in run."""
    on_demand = _ant_after_random_efforts("cuda:0", compiled_in=False)
    sim = sim_utils.SimulationContext.instance()
    physics = sim.physics
    physics.wp_model.opt.run_rne_postconstraint = True  # MuJoCo Warp's forward runs the pass itself
    physics._graphs.clear()
    physics.forward()  # the same state: forward is a function of it
    torch.testing.assert_close(physics.data("cfrc_int").cpu(), on_demand["cfrc_int"], atol=1e-4, rtol=1e-4)
    torch.testing.assert_close(physics.data("cfrc_ext").cpu(), on_demand["cfrc_ext"], atol=1e-4, rtol=1e-4)
    sim_utils.SimulationContext.clear_instance()
    compiled_in = _ant_after_random_efforts("cuda:0", compiled_in=True)
    assert compiled_in["cfrc_ext"][:, 2:].abs().amax() > 1.0
    # two GPU runs: contacts are gathered in no fixed order, so the float sums may differ slightly
    torch.testing.assert_close(on_demand["wrench"], compiled_in["wrench"], atol=2e-2, rtol=2e-2)


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
