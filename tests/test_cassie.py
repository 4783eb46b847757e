"""Agility Cassie: the MJCF model, CASSIE_CFG, its closed loop, and the velocity tasks.

The model has Isaac Lab's twelve joints; the achilles rod of each leg, which makes the tarsus
(``ankle_joint``) follow the knee (``thigh_joint``), is a fixed-length tendon held by an equality
constraint. Checked here: the names, the order (Isaac Lab's, level by level), the published mass, that
the loop holds (under a millimetre) while the driven joints sweep their ranges and while standing, that
the robot stands on its soles under stiff drives (Isaac Lab's gains leave balancing to the policy, as
for G1 and H1: tests/test_humanoid_robots.py), and that the tasks and Isaac Lab's own task files run.
"""

from __future__ import annotations

import importlib
import math
import sys
from pathlib import Path

import gymnasium as gym
import mujoco
import pytest
import torch
from test_humanoid_robots import hung, scene_with, stiff

import simlab.tasks  # noqa: F401 - registers the tasks
from simlab.envs import ManagerBasedRLEnv
from simlab.robots import CASSIE_CFG, cassie
from simlab.tasks.utils.parse_cfg import parse_env_cfg

MODEL = cassie.ASSETS_DIR + "/agility_cassie.xml"
LEG = ("hip_abduction", "hip_rotation", "hip_flexion", "thigh_joint", "ankle_joint", "toe_joint")
# MuJoCo's depth-first order, and Isaac Lab's (PhysX's level by level: both legs' joint at each depth)
MODEL_JOINTS = [f"{j}_{s}" for s in ("left", "right") for j in LEG]
ISAAC_LAB_JOINTS = [f"{j}_{s}" for j in LEG for s in ("left", "right")]
PUBLISHED_MASS = 33.312  # menagerie's agility_cassie, the sum of its 25 links [kg]
ROD = 0.5012  # achilles rod length, ball centre to ball centre [m]
N = 2


def rod_error(sim) -> torch.Tensor:
    """How far each achilles rod is from its length [m], (envs, 2)."""
    return (sim.physics.data("ten_length") - ROD).abs()


def test_model_names_mass_and_loops():
    model = mujoco.MjModel.from_xml_path(MODEL)
    assert model.nu == 0 and model.jnt_type[0] == mujoco.mjtJoint.mjJNT_FREE
    assert [model.joint(j).name for j in range(1, model.njnt)] == MODEL_JOINTS
    assert (model.jnt_type[1:] == mujoco.mjtJoint.mjJNT_HINGE).all() and (model.jnt_limited[1:] == 1).all()
    assert model.body(1).name == "pelvis"
    assert sum(model.body_mass) == pytest.approx(PUBLISHED_MASS, rel=0.05)
    # one equality per leg, on a two-site tendon of the rod's length at the reference pose
    assert model.neq == 2 and (model.eq_type == mujoco.mjtEq.mjEQ_TENDON).all()
    assert model.tendon_length0 == pytest.approx([ROD, ROD], abs=1e-3)
    # the menagerie ranges, in radians: knee -164..-37 deg, tarsus 50..170 deg
    knee, tarsus = model.joint("thigh_joint_left").range, model.joint("ankle_joint_left").range
    assert knee == pytest.approx([math.radians(-164), math.radians(-37)])
    assert tarsus == pytest.approx([math.radians(50), math.radians(170)])


def test_articulation_names_order_gains_and_default_pose():
    sim, scene = scene_with(CASSIE_CFG)
    robot = scene["robot"]
    assert robot.joint_names == ISAAC_LAB_JOINTS
    assert robot.body_names[0] == "pelvis" and {"left_toe", "right_toe"} <= set(robot.body_names)
    torch.testing.assert_close(robot.data.joint_pos, robot.data.default_joint_pos)
    kp = dict(zip(robot.joint_names, robot.data.joint_stiffness[0].tolist()))
    kd = dict(zip(robot.joint_names, robot.data.joint_damping[0].tolist()))
    limits = dict(zip(robot.joint_names, robot.data.joint_effort_limits[0].tolist()))
    assert (kp["hip_abduction_left"], kp["hip_flexion_right"], kp["thigh_joint_left"], kp["toe_joint_right"]) == (
        100,
        200,
        200,
        20,
    )
    assert (kd["hip_rotation_left"], kd["thigh_joint_right"], kd["toe_joint_left"]) == (3, 6, 1)
    assert (limits["hip_flexion_left"], limits["toe_joint_left"]) == (200, 20)
    # the tarsus is passive: no group drives it
    driven = sorted(j for a in robot.actuators.values() for j in a.joint_names)
    assert driven == sorted(j for j in ISAAC_LAB_JOINTS if not j.startswith("ankle"))
    assert kp["ankle_joint_left"] == 0 and kd["ankle_joint_right"] == 0
    # the default pose closes the loop: each rod at its length
    assert rod_error(sim).max() < 2e-4


def test_loop_holds_while_the_legs_sweep_their_ranges():
    """Hung by the pelvis, every driven joint follows a sine across 80 % of its soft range (the knee from
    -146 to -55 degrees) at 0.5 Hz for 3 s under Isaac Lab's gains; the tarsus, moved only by the rod,
    follows. (A step of the knee's target by 0.8 rad at once stretches the rods by up to 4 mm for a few
    steps: the constraint is soft, its time constant twice the 5 ms step.)"""
    sim, scene = scene_with(hung(CASSIE_CFG))
    robot = scene["robot"]
    low, high = robot.data.soft_joint_pos_limits[0, :, 0], robot.data.soft_joint_pos_limits[0, :, 1]
    mid, half = (low + high) / 2, (high - low) / 2
    tarsus = robot.find_joints("ankle_joint_.*")[0]
    worst, seen = 0.0, []
    for i in range(600):  # 3 s
        t = i * sim.get_physics_dt()
        sweep = mid + 0.8 * half * torch.sin(2 * math.pi * 0.5 * t + 0.7 * torch.arange(robot.num_joints))
        ramp = min(1.0, t / 0.5)  # from the default pose into the sweep over 0.5 s
        robot.set_joint_position_target(robot.data.default_joint_pos + ramp * (sweep - robot.data.default_joint_pos))
        scene.write_data_to_sim()
        sim.step()
        scene.update(sim.get_physics_dt())
        worst = max(worst, float(rod_error(sim).max()))
        seen.append(robot.data.joint_pos[0, tarsus].clone())
    seen = torch.stack(seen)
    assert (seen.max(0).values - seen.min(0).values).min() > 1.0, "the tarsus swings over a radian"
    assert worst < 1e-3, worst


def _stands(engine: str) -> None:
    sim, scene = scene_with(stiff(CASSIE_CFG), engine)
    robot, contacts = scene["robot"], scene["contacts"]
    robot.set_joint_position_target(robot.data.default_joint_pos)
    heights, worst = [], 0.0
    for _ in range(600):  # 3 s
        scene.write_data_to_sim()
        sim.step()
        scene.update(sim.get_physics_dt())
        heights.append(robot.data.root_pos_w[:, 2].clone())
        if len(heights) > 100:  # after landing (its impact stretches the rods by about 1.3 mm)
            worst = max(worst, float(rod_error(sim).max()))
    settled = torch.stack(heights)[100:]
    assert settled.min() > 0.95 and settled.max() < 1.01, (settled.min(), settled.max())
    assert (robot.data.projected_gravity_b[:, 2] < -0.99).all(), "upright"
    assert worst < 1e-3, "the rods hold the weight"
    toes, _ = contacts.find_bodies(".*toe")
    weight = float(robot.data.default_mass[0].sum()) * 9.81
    torch.testing.assert_close(
        contacts.data.net_forces_w[:, toes, 2].sum(1), torch.full((N,), weight), rtol=0.02, atol=0
    )


def test_stands_on_its_soles_under_stiff_drives():
    _stands("mujoco")


@pytest.mark.slow
def test_stands_on_its_soles_under_stiff_drives_on_mujoco_warp():
    pytest.importorskip("mujoco_warp")
    _stands("mujoco_warp")


def test_isaac_labs_gains_alone_do_not_hold_it_up():
    """Why the standing test stiffens the drives: under CASSIE_CFG's gains, targets at the default pose,
    the knees fold and the pelvis drops (a policy has to carry the robot)."""
    sim, scene = scene_with(CASSIE_CFG)
    robot = scene["robot"]
    robot.set_joint_position_target(robot.data.default_joint_pos)
    for _ in range(400):  # 2 s
        scene.write_data_to_sim()
        sim.step()
        scene.update(sim.get_physics_dt())
    assert (robot.data.root_pos_w[:, 2] < 0.8).all()


def make(task: str) -> ManagerBasedRLEnv:
    cfg = parse_env_cfg(task, device="cpu", num_envs=N)
    cfg.seed = 0
    return gym.make(task, cfg=cfg).unwrapped


def steps_finite(env: ManagerBasedRLEnv, steps: int = 20) -> None:
    obs, _ = env.reset()
    for _ in range(steps):
        obs, reward, *_ = env.step(0.3 * torch.randn(N, env.action_manager.total_action_dim))
        assert torch.isfinite(obs["policy"]).all() and torch.isfinite(reward).all()


@pytest.mark.parametrize("task", ["Flat", "Rough", "Flat-Play", "Rough-Play"])
def test_task_builds_and_steps(task):
    terrain, _, play = task.partition("-")
    task_id = f"simlab/Velocity-{terrain}-Cassie{'-' + play if play else ''}-v0"
    assert (
        gym.spec(task_id)
        .kwargs["success_criterion_entry_point"]
        .startswith("simlab.tasks.manager_based.locomotion.velocity.criterion:")
    )
    env = make(task_id)
    try:
        assert env.action_manager.total_action_dim == 12
        # 9 (base velocities, gravity) + 3 (command) + 3 x 12 joints, + the height scan on rough ground
        assert env.observation_manager.group_obs_dim["policy"][0] == 48 + (17 * 11 if terrain == "Rough" else 0)
        steps_finite(env)
    finally:
        env.close()


def ported(terrain: str):
    path = str(Path(__file__).parent / "ported")
    sys.path.insert(0, path)
    try:
        module = importlib.import_module(f"isaaclab_velocity_cassie.{terrain.lower()}_env_cfg")
    finally:
        sys.path.remove(path)
    return getattr(module, f"Cassie{terrain}EnvCfg")()


@pytest.mark.parametrize("terrain", ["Flat", "Rough"])
def test_isaac_labs_own_task_config_runs_after_the_import_mapping(terrain):
    cfg = ported(terrain)
    ours = parse_env_cfg(f"simlab/Velocity-{terrain}-Cassie-v0", device="cpu", num_envs=N)
    weights = {name: term.weight for name, term in vars(cfg.rewards).items() if term is not None}
    assert weights == {name: term.weight for name, term in vars(ours.rewards).items() if term is not None}
    # Isaac Lab's release-2.x file leaves the centre-of-mass event on a body named "base", which Cassie
    # lacks; Isaac Lab's later file turns it off, as simlab's task does.
    cfg.events.base_com = None
    cfg.scene.num_envs, cfg.sim.device, cfg.seed = N, "cpu", 0
    env = ManagerBasedRLEnv(cfg)
    try:
        steps_finite(env, 5)
    finally:
        env.close()
