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
