"""The G1 and H1 velocity tasks: registration, a few steps of each, the biped air-time reward on
known contact states, and Isaac Lab's own g1 and h1 task configs run after the import mapping
(``tests/ported/isaaclab_velocity_{g1,h1}``) with the same terms and weights as simlab's."""

from __future__ import annotations

import importlib
import sys
from pathlib import Path

import gymnasium as gym
import pytest
import torch

import simlab.tasks  # noqa: F401 - registers the tasks
from simlab.envs import ManagerBasedRLEnv
from simlab.managers import SceneEntityCfg
from simlab.tasks.manager_based.locomotion.velocity import mdp
from simlab.tasks.utils.parse_cfg import parse_env_cfg

N = 4
PORTED = Path(__file__).parent / "ported"

# policy observation size: 9 (base velocities, gravity) + 3 (command) + 3 x joints, + the height scan;
# simlab's G1 tasks drive and see its 23 walking joints, Isaac Lab's all 37
OBS = {"G1": 9 + 3 + 3 * 23, "H1": 9 + 3 + 3 * 19}
ISAAC_LAB_OBS = {"G1": 9 + 3 + 3 * 37, "H1": OBS["H1"]}
# the terms simlab tunes for MuJoCo (the task files' docstrings say why): tracking weighted 2 and 2
RETUNED = {"track_lin_vel_xy_exp": 2.0, "track_ang_vel_z_exp": 2.0}
SCAN = 17 * 11


def make(task: str, num_envs: int = N) -> ManagerBasedRLEnv:
    cfg = parse_env_cfg(task, device="cpu", num_envs=num_envs)
    cfg.seed = 0
    return gym.make(task, cfg=cfg).unwrapped


def test_task_ids():
    for robot in ("G1", "H1"):
        for terrain in ("Flat", "Rough"):
            for play in ("", "-Play"):
                assert f"simlab/Velocity-{terrain}-{robot}{play}-v0" in gym.registry


@pytest.mark.parametrize("robot", ["G1", "H1"])
@pytest.mark.parametrize("task", ["Flat", "Rough", "Flat-Play"])
def test_task_resets_and_steps(robot, task):
    terrain, _, play = task.partition("-")
    env = make(f"simlab/Velocity-{terrain}-{robot}{'-' + play if play else ''}-v0")
    try:
        obs, _ = env.reset()
        assert obs["policy"].shape == (N, OBS[robot] + (SCAN if terrain == "Rough" else 0))
        assert env.graph_blockers() == [], "the step can be captured as a CUDA graph"
        actions = env.action_manager.total_action_dim
        for _ in range(20):
            obs, reward, terminated, truncated, _ = env.step(0.3 * torch.randn(N, actions))
            assert torch.isfinite(obs["policy"]).all() and torch.isfinite(reward).all()
        terms = env.reward_manager.active_terms
        assert {"feet_air_time", "feet_slide", "dof_pos_limits", "joint_deviation_hip"} <= set(terms)
        assert env.reward_manager.get_term_cfg("feet_air_time").func is mdp.feet_air_time_positive_biped
    finally:
        env.close()


@pytest.mark.parametrize("robot", ["G1", "H1"])
def test_flat_tasks_contact_buffers_hold_the_robot_fallen_on_the_ground(robot):
    """The flat tasks reserve MuJoCo Warp buffers from measured peaks (``sim.mujoco.nconmax`` / ``njmax``
    per world, below MuJoCo Warp's estimate): the worst case they must hold is the robot lying on the
    ground. Eight worlds drop it 0.25 m onto its front, back and sides, the first four with their joints
    held at the default pose, the others driven to random points of their ranges (limbs spread, bent or
    crossed), for 2 s; MuJoCo C counts each world's contacts and constraint rows after every physics step.
    The reserved sizes hold 1.5 times the peaks (MuJoCo Warp's collision functions are its own, so a pair
    may give a few more contacts there). A walking robot under random actions peaks lower (8 contacts,
    34 rows for either robot)."""
    import mujoco

    worlds = 8
    env = make(f"simlab/Velocity-Flat-{robot}-v0", num_envs=worlds)
    try:
        env.reset()
        robot_asset, physics = env.scene["robot"], env.sim.physics
        model, data = env.sim.model, mujoco.MjData(env.sim.model)
        generator = torch.Generator().manual_seed(0)
        low, high = robot_asset.data.joint_pos_limits.unbind(-1)
        default = robot_asset.data.default_joint_pos
        targets = low + torch.rand(low.shape, generator=generator) * (high - low)
        targets[:4] = default[:4]
        # lying: a quarter turn about +y (on the front), -y (back), +x and -x (sides), 0.25 m up
        axes = torch.tensor([[0.0, 1.0, 0.0], [0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [-1.0, 0.0, 0.0]]).repeat(2, 1)
        half = torch.tensor(torch.pi / 4)
        quat = torch.cat((torch.cos(half).expand(worlds, 1), torch.sin(half) * axes), dim=-1)
        position = env.scene.env_origins + torch.tensor([0.0, 0.0, 0.25])
        robot_asset.write_root_pose_to_sim(torch.cat((position, quat), dim=-1))
        robot_asset.write_root_velocity_to_sim(torch.zeros(worlds, 6))
        robot_asset.write_joint_state_to_sim(default, torch.zeros_like(default))
        qpos, qvel = physics.data("qpos"), physics.data("qvel")
        contacts, rows = [0] * worlds, [0] * worlds
        for _ in range(round(2.0 / env.physics_dt)):
            robot_asset.set_joint_position_target(targets)
            env.scene.write_data_to_sim()
            env.sim.step(render=False)
            for world in range(worlds):
                data.qpos[:], data.qvel[:] = qpos[world].numpy(), qvel[world].numpy()
                mujoco.mj_forward(model, data)
                contacts[world], rows[world] = max(contacts[world], data.ncon), max(rows[world], data.nefc)
        # lying on the ground at the end, not standing
        height = qpos[:, 2] - env.scene.env_origins[:, 2]
        assert (height < 0.35).all(), height
        reserved = env.cfg.sim.mujoco  # peaks measured: G1 15 contacts / 64 rows, H1 11 / 44
        assert reserved.nconmax >= 1.5 * max(contacts), f"contacts per world {contacts}, nconmax {reserved.nconmax}"
        assert reserved.njmax >= 1.5 * max(rows), f"constraint rows per world {rows}, njmax {reserved.njmax}"
    finally:
        env.close()


def test_feet_air_time_positive_biped_pays_single_support_up_to_the_threshold():
    env = make("simlab/Velocity-Flat-G1-v0")
    try:
        env.reset()
        sensor = env.scene["contact_forces"]
        feet = SceneEntityCfg("contact_forces", body_names=".*_ankle_roll_link")
        feet.resolve(env.scene)
        left, right = feet.body_ids
        air, contact = sensor.data.current_air_time, sensor.data.current_contact_time
        air.zero_(), contact.zero_()
        # env 0: left stance 0.3 s, right swing 0.2 s -> 0.2; env 1: the same longer than the threshold -> 0.4;
        # env 2: both feet down (double support) -> 0; env 3: both in the air -> 0
        contact[0, left], air[0, right] = 0.3, 0.2
        contact[1, left], air[1, right] = 0.9, 0.7
        contact[2, left], contact[2, right] = 0.3, 0.5
        air[3, left], air[3, right] = 0.1, 0.1
        command = env.command_manager.get_command("base_velocity")
        command[:] = torch.tensor([0.5, 0.0, 0.0])
        reward = mdp.feet_air_time_positive_biped(env, "base_velocity", threshold=0.4, sensor_cfg=feet)
        torch.testing.assert_close(reward, torch.tensor([0.2, 0.4, 0.0, 0.0]))
        command[:] = torch.tensor([0.05, 0.05, 1.0])  # turning in place: no steps asked for
        assert not mdp.feet_air_time_positive_biped(env, "base_velocity", threshold=0.4, sensor_cfg=feet).any()
    finally:
        env.close()


def ported(robot: str, terrain: str):
    sys.path.insert(0, str(PORTED))
    try:
        module = importlib.import_module(f"isaaclab_velocity_{robot.lower()}.{terrain.lower()}_env_cfg")
    finally:
        sys.path.remove(str(PORTED))
    return getattr(module, f"{robot}{terrain}EnvCfg")()


def weights(cfg) -> dict[str, float]:
    return {name: term.weight for name, term in vars(cfg.rewards).items() if term is not None}


@pytest.mark.parametrize("robot", ["G1", "H1"])
@pytest.mark.parametrize("terrain", ["Flat", "Rough"])
def test_isaac_labs_own_task_config_runs_after_the_import_mapping(robot, terrain):
    cfg = ported(robot, terrain)
    # the same terms and commands as simlab's registered task; the weights too, but for the retuned ones
    ours = parse_env_cfg(f"simlab/Velocity-{terrain}-{robot}-v0", device="cpu", num_envs=N)
    assert weights(cfg).keys() == weights(ours).keys()
    assert {**weights(cfg), **RETUNED} == weights(ours)
    assert cfg.commands.base_velocity.ranges == ours.commands.base_velocity.ranges
    cfg.scene.num_envs, cfg.sim.device, cfg.seed = N, "cpu", 0
    env = ManagerBasedRLEnv(cfg)
    try:
        obs, _ = env.reset()
        assert obs["policy"].shape == (N, ISAAC_LAB_OBS[robot] + (SCAN if terrain == "Rough" else 0))
        for _ in range(5):
            obs, reward, *_ = env.step(torch.zeros(N, env.action_manager.total_action_dim))
            assert torch.isfinite(obs["policy"]).all() and torch.isfinite(reward).all()
    finally:
        env.close()


def test_biped_criterion_counts_the_falls_of_an_idle_robot():
    from simlab.tasks.utils.criteria import criterion_for

    criterion = criterion_for("simlab/Velocity-Flat-G1-v0")
    assert criterion is not criterion_for("simlab/Velocity-Rough-G1-v0")
    assert criterion.play_seconds(5.0) == 20.0, "a verdict needs a whole episode"
    on_step, sums = criterion.make_hook()
    env = make("simlab/Velocity-Flat-G1-v0")
    try:
        obs, _ = env.reset()
        actions = torch.zeros(N, env.action_manager.total_action_dim)
        for _ in range(150):  # 3 s at the default pose targets: the G1 cannot balance without a policy
            obs, *_ = env.step(actions)
            on_step(env, obs, actions)
    finally:
        env.close()
    assert sums["steps"] == 150 and sums["samples"] == 150 * N
    assert sums["falls"] >= N, "each robot fell at least once"
    score, passed = criterion.judge({}, sums)
    assert score == sums["speed"] / sums["samples"] and not passed
    # the same errors without the falls pass
    assert criterion.judge({}, {**sums, "speed": 0.2 * sums["samples"], "yaw_rate": 0.2 * sums["samples"], "falls": 0})[
        1
    ]
    # one fall per 20 env-seconds in 5 % of the envs is the limit
    steady = {"speed": 0.0, "yaw_rate": 0.0, "samples": 1000 * 100, "steps": 1000, "seconds": 20.0}
    assert criterion.judge({}, {**steady, "falls": 4})[1] and not criterion.judge({}, {**steady, "falls": 5})[1]


def test_rough_criterion_reads_the_curriculum_level():
    from simlab.tasks.utils.criteria import criterion_for

    criterion = criterion_for("simlab/Velocity-Rough-H1-v0")
    on_step, level = criterion.make_hook()
    env = make("simlab/Velocity-Rough-H1-v0")
    try:
        obs, _ = env.reset()
        levels = env.scene.terrain.terrain_levels
        for rows, verdict in (([4, 4, 3, 2], True), ([3, 2, 3, 2], False)):
            levels[:] = torch.tensor(rows)
            on_step(env, obs, None)
            assert criterion.judge({}, level) == (sum(rows) / N, verdict)
    finally:
        env.close()
