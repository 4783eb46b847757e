"""Isaac Lab 3.0's own task files (issue 42.3), written out under the 3.0 mapping in tests/ported3 (what
differs besides the imports at each file's top): each builds with ``simlab.v3.envs.ManagerBasedRLEnv`` on
the CPU and steps, and its MDP is compared with simlab's 2.x task of the same name."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest
import torch

from simlab.v3.envs import ManagerBasedRLEnv

PORTED3 = Path(__file__).parent / "ported3"


@pytest.fixture
def ported3():
    sys.path.insert(0, str(PORTED3))
    yield
    sys.path.remove(str(PORTED3))
    for name in [m for m in sys.modules if m.split(".")[0].startswith("isaaclab3_")]:
        del sys.modules[name]


def _terms(group) -> dict:
    """A manager group's active terms (a term set to None is off), by name."""
    return {k: v for k, v in vars(group).items() if v is not None and hasattr(v, "func")}


def _step(cfg, num_envs: int = 2, steps: int = 20) -> ManagerBasedRLEnv:
    cfg.scene.num_envs = num_envs
    cfg.sim.device = "cpu"
    env = ManagerBasedRLEnv(cfg)
    obs, _ = env.reset(seed=0)
    generator = torch.Generator().manual_seed(0)
    for _ in range(steps):
        actions = torch.rand(num_envs, env.action_manager.total_action_dim, generator=generator) * 2 - 1
        obs, reward, _, _, _ = env.step(actions)
        assert all(torch.isfinite(v).all() for v in obs.values())
        assert torch.isfinite(reward).all()
    return env


def test_3_0_go2_flat_velocity_task_steps_with_the_2_x_tasks_rewards(ported3):
    from isaaclab3_velocity.config.go2.flat_env_cfg import UnitreeGo2FlatEnvCfg as Go2Flat3

    from simlab.tasks.manager_based.locomotion.velocity.config.go2.flat_env_cfg import UnitreeGo2FlatEnvCfg as Go2Flat2

    cfg3, cfg2 = Go2Flat3(), Go2Flat2()
    # the reward and termination terms, their weights and parameters, and the policy's observations are 2.x's
    for group in ("rewards", "terminations"):
        terms3, terms2 = _terms(getattr(cfg3, group)), _terms(getattr(cfg2, group))
        assert list(terms3) == list(terms2)
        for name, term in terms3.items():
            assert term.func.__name__ == terms2[name].func.__name__, name
            assert getattr(term, "weight", None) == getattr(terms2[name], "weight", None), name
            assert str(term.params) == str(terms2[name].params), name
    assert list(_terms(cfg3.observations.policy)) == list(_terms(cfg2.observations.policy))
    # 3.0's Go2 keeps the shared events that 2.x's Go2 config turned off or narrowed
    assert cfg3.events.push_robot is not None and cfg2.events.push_robot is None
    assert cfg3.events.add_base_mass.params["operation"] == "scale"  # 2.x's Go2: "add" (-1, 3) kg

    env = _step(cfg3)
    try:
        # the newton_mjwarp default is MuJoCo's: 2 substeps of dt / 2, the flat config's njmax / nconmax
        assert env.sim.model.opt.timestep == pytest.approx(0.0025)
        assert (env.cfg.sim.mujoco.njmax, env.cfg.sim.mujoco.nconmax) == (65, 35)
        assert env.observation_manager.group_obs_dim["policy"] == (48,)
        assert env.reward_manager.active_terms == list(_terms(cfg2.rewards))
        # the robot stands on its feet on the plane: the feet touch, the base does not
        contact = env.scene["contact_forces"]
        feet, _ = contact.find_bodies(".*_foot")
        assert (contact.data.net_forces_w[:, feet].norm(dim=-1).sum(-1) > 0).all()
    finally:
        env.close()


def test_3_0_go2_rough_velocity_task_steps_on_generated_terrain_with_its_height_scan(ported3):
    from isaaclab3_velocity.config.go2.rough_env_cfg import UnitreeGo2RoughEnvCfg

    cfg = UnitreeGo2RoughEnvCfg()
    generator = cfg.scene.terrain.terrain_generator
    generator.num_rows = generator.num_cols = 2  # a small grid of 3.0's (Go2-scaled) rough terrains: fast
    assert generator.curriculum  # the terrain-level curriculum is on
    assert generator.sub_terrains["pyramid_stairs"].step_height_range == (0.025, 0.12)
    env = _step(cfg, steps=10)
    try:
        # njmax / nconmax of the rough preset, 2 substeps; the 1.6 x 1.0 m scan at 0.1 m: 17 x 11 rays
        assert (env.cfg.sim.mujoco.njmax, env.cfg.sim.mujoco.nconmax) == (1000, 300)
        assert env.sim.model.opt.timestep == pytest.approx(0.0025)
        assert env.observation_manager.group_obs_dim["policy"] == (48 + 17 * 11,)
        assert "terrain_levels" in env.curriculum_manager.active_terms
    finally:
        env.close()


def test_3_0_franka_reach_steps_and_its_success_and_pose_errors_read_one_orientation(ported3):
    from isaaclab3_reach import mdp as reach_mdp
    from isaaclab3_reach.config.franka.franka_env_cfg import FrankaReachEnvCfg

    import simlab.utils.math as math2
    from simlab.managers import SceneEntityCfg
    from simlab.v3.envs import mdp

    env = _step(FrankaReachEnvCfg())
    try:
        # the default is PhysX, held: the env runs on simlab's MuJoCo options
        assert env.sim.model.opt.timestep == pytest.approx(1 / 120)
        assert env.observation_manager.group_obs_dim["policy"] == (9 + 9 + 7 + 7,)
        term, robot = env.command_manager.get_term("ee_pose"), env.scene["robot"]
        hand = SceneEntityCfg("robot", body_names=["panda_hand"])
        hand.resolve(env.scene)
        # command the hand's own pose (in the root frame, simlab's (w, x, y, z)): no error, success
        data = robot.data
        pos_b, quat_b = math2.subtract_frame_transforms(
            data.root_pos_w, data.root_quat_w, data.body_pos_w[:, term.body_idx], data.body_quat_w[:, term.body_idx]
        )
        term.pose_command_b[:] = torch.cat((pos_b, quat_b), dim=-1)
        assert mdp.position_command_error(env, asset_cfg=hand) == pytest.approx(torch.zeros(2), abs=1e-5)
        assert mdp.orientation_command_error(env, asset_cfg=hand) == pytest.approx(torch.zeros(2), abs=1e-3)
        args = {"command_name": "ee_pose", "position_threshold": 0.05, "orientation_threshold": 0.2}
        assert reach_mdp.pose_command_success(env, **args).all()
        # turn the command 0.5 rad about the root's z: both 3.0's success and simlab's error see 0.5 rad
        turn = math2.quat_from_euler_xyz(torch.zeros(2), torch.zeros(2), torch.full((2,), 0.5))
        term.pose_command_b[:, 3:] = math2.quat_mul(turn, quat_b)
        assert mdp.orientation_command_error(env, asset_cfg=hand) == pytest.approx(torch.full((2,), 0.5), abs=1e-3)
        assert not reach_mdp.pose_command_success(env, **args).any()
        assert reach_mdp.pose_command_success(env, **{**args, "orientation_threshold": 0.51}).all()
    finally:
        env.close()


def test_3_0_franka_reach_diffik_preset_steps(ported3):
    from isaaclab3_reach.config.franka.franka_env_cfg import FrankaReachEnvCfg

    cfg = FrankaReachEnvCfg()
    cfg.actions.arm_action = cfg.actions.arm_action.diffik
    env = _step(cfg, steps=10)
    try:
        assert env.action_manager.total_action_dim == 6  # relative pose
    finally:
        env.close()
