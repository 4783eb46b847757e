"""Isaac Lab's Allegro Hand task files, ported by the import mapping alone, run on simlab.

``tests/ported/allegro_hand_env_cfg.py`` and ``tests/ported/inhand_manipulation_env.py`` are Isaac
Lab's files with their ``isaaclab`` imports rewritten and nothing else: the config spawns the DexCube
by its Nucleus USD path (simlab stands in a box of its size), reads joint limits with
``root_physx_view.get_dof_limits()``, resets by env ids and draws its goal marker in the step. The
test steps the ported task beside simlab's own (same MuJoCo settings, same seed and actions) and
checks that they observe and earn the same. ``tests/ported/inhand_env_cfg.py`` (the manager-based
in-hand config, with the Allegro Hand set as Isaac Lab's ``allegro_env_cfg.py`` sets it) is checked
the same way against ``simlab/Repose-Cube-Allegro-v0``.
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

import pytest
import torch
from conftest import load_script

from simlab.tasks.direct.allegro_hand.allegro_hand_env_cfg import AllegroHandEnvCfg
from simlab.tasks.direct.inhand_manipulation.inhand_manipulation_env import InHandManipulationEnv, unscale

PORTED = Path(__file__).parent / "ported"
NUM_ENVS = 4


@pytest.fixture(scope="module")
def ported():
    cfg_module = load_script(PORTED / "allegro_hand_env_cfg.py", "isaaclab_allegro_hand_env_cfg")
    env_module = load_script(PORTED / "inhand_manipulation_env.py", "isaaclab_inhand_manipulation_env")
    yield cfg_module, env_module
    for name in ("isaaclab_allegro_hand_env_cfg", "isaaclab_inhand_manipulation_env"):
        sys.modules.pop(name, None)


def test_only_import_lines_name_simlab():
    for name in ("allegro_hand_env_cfg.py", "inhand_manipulation_env.py", "inhand_env_cfg.py"):
        code = [line for line in (PORTED / name).read_text().splitlines() if line and not line.startswith("#")]
        assert not any("isaaclab" in line for line in code)
        simlab_lines = [line.strip() for line in code if "simlab" in line]
        assert simlab_lines and all(re.match(r"(from|import) simlab", line) for line in simlab_lines), simlab_lines


def make(env_class, cfg):
    cfg.seed = 0
    cfg.scene.num_envs = NUM_ENVS
    cfg.sim.device = "cpu"
    return env_class(cfg)


def test_ported_allegro_task_steps_as_simlab_s_own(ported):
    cfg_module, env_module = ported
    ported_cfg = cfg_module.AllegroHandEnvCfg()
    ported_cfg.sim.mujoco = AllegroHandEnvCfg().sim.mujoco  # simlab's MuJoCo settings for the task, on both
    envs = [make(env_module.InHandManipulationEnv, ported_cfg), make(InHandManipulationEnv, AllegroHandEnvCfg())]
    try:
        assert envs[0].object.data.default_mass[0].item() == pytest.approx(400.0 * 0.072**3, rel=1e-4)
        first = [env.reset(seed=0)[0]["policy"] for env in envs]
        torch.testing.assert_close(first[0], first[1])
        generator = torch.Generator().manual_seed(0)
        for _ in range(15):
            # small moves about the joints' present positions (large ones let the cube fall, and the two
            # tasks reset a part of their envs with different draws)
            joint_pos = envs[1].hand.data.joint_pos
            actions = unscale(joint_pos, envs[1].hand_dof_lower_limits, envs[1].hand_dof_upper_limits)
            actions = actions + 0.1 * (2 * torch.rand(NUM_ENVS, 16, generator=generator) - 1)
            (obs_a, rew_a, term_a, trunc_a, _), (obs_b, rew_b, term_b, trunc_b, _) = (env.step(actions) for env in envs)
            assert not (term_a | trunc_a).any()  # no partial reset: the two draw their noise differently then
            torch.testing.assert_close(obs_a["policy"], obs_b["policy"], atol=1e-4, rtol=1e-4)
            torch.testing.assert_close(rew_a, rew_b, atol=1e-4, rtol=1e-4)
            torch.testing.assert_close(term_a, term_b)
    finally:
        for env in envs:
            env.close()


def test_ported_allegro_task_resets_and_redraws_goals_as_simlab_s_own(ported):
    """The draws and the math of simlab's goal redraws and resets (a folded random rotation, the rotation
    to the goal in one product, the reset noise) against Isaac Lab's own code: with a goal tolerance past
    any rotation every env reaches its goal in every step and gets a new one, and then every env is reset
    at once. Each env steps from the same torch seed (simlab draws for all envs every step, Isaac Lab only
    where one is due: with every goal due both draw the same)."""
    cfg_module, env_module = ported
    cfgs = [cfg_module.AllegroHandEnvCfg(), AllegroHandEnvCfg()]
    cfgs[0].sim.mujoco = cfgs[1].sim.mujoco
    for cfg in cfgs:
        cfg.success_tolerance = 4.0  # > pi: every goal reached
    envs = [make(env_module.InHandManipulationEnv, cfgs[0]), make(InHandManipulationEnv, cfgs[1])]

    def step_both(seed):
        hold = unscale(envs[1].hand.data.joint_pos, envs[1].hand_dof_lower_limits, envs[1].hand_dof_upper_limits)
        goals = envs[1].goal_rot.clone()
        results = []
        for env in envs:
            torch.manual_seed(seed)
            results.append(env.step(hold))
        (obs_a, rew_a, term_a, trunc_a, _), (obs_b, rew_b, term_b, trunc_b, _) = results
        assert not (term_a | trunc_a).any()
        torch.testing.assert_close(obs_a["policy"], obs_b["policy"], atol=1e-4, rtol=1e-4)
        torch.testing.assert_close(rew_a, rew_b, atol=1e-4, rtol=1e-4)
        torch.testing.assert_close(envs[0].goal_rot, envs[1].goal_rot, atol=1e-6, rtol=0)
        assert (rew_b > 200.0).all() and not torch.allclose(envs[1].goal_rot, goals)  # the bonus (250), new goals

    try:
        for env in envs:
            env.reset(seed=0)
        for seed in range(1, 5):  # not reset()'s seed 0: its first draw was the first goal
            step_both(seed)
        assert (envs[1].successes == 4).all()
        for env in envs:  # every env reset at once: the same draws in both
            torch.manual_seed(20)
            env._reset_idx(torch.arange(NUM_ENVS))
        for seed in range(30, 33):
            step_both(seed)
    finally:
        for env in envs:
            env.close()


def test_ported_manager_based_inhand_config_steps_as_simlab_s_own():
    """Isaac Lab's manager-based in-hand config (``tests/ported/inhand_env_cfg.py``) with the Allegro
    Hand, as Isaac Lab's ``allegro_env_cfg.py`` sets it, beside ``simlab/Repose-Cube-Allegro-v0``."""
    from simlab.envs import ManagerBasedRLEnv
    from simlab.robots import ALLEGRO_HAND_CFG
    from simlab.tasks.manager_based.manipulation.inhand.config.allegro_hand.allegro_env_cfg import AllegroCubeEnvCfg

    module = load_script(PORTED / "inhand_env_cfg.py", "isaaclab_inhand_env_cfg")
    try:
        ported_cfg = module.InHandObjectEnvCfg()
        ported_cfg.scene.robot = ALLEGRO_HAND_CFG.replace(prim_path="{ENV_REGEX_NS}/Robot")
        own_cfg = AllegroCubeEnvCfg()
        ported_cfg.sim.mujoco = own_cfg.sim.mujoco  # simlab's MuJoCo settings for the task, on both
        envs = []
        for cfg in (ported_cfg, own_cfg):
            cfg.seed = 0
            cfg.scene.num_envs = NUM_ENVS
            cfg.sim.device = "cpu"
            cfg.observations.policy.enable_corruption = False  # noise: both envs draw from one generator
            torch.manual_seed(0)  # the start-up randomization draws from torch's generator
            envs.append(ManagerBasedRLEnv(cfg))
        first = [env.reset(seed=0)[0]["policy"] for env in envs]
        assert first[0].shape == (NUM_ENVS, 72)
        torch.testing.assert_close(first[0], first[1])
        generator = torch.Generator().manual_seed(0)
        for _ in range(8):  # before the first cube leaves its hand (the 10th step, env 3)
            actions = 0.2 * (2 * torch.rand(NUM_ENVS, 16, generator=generator) - 1)
            (obs_a, rew_a, term_a, trunc_a, _), (obs_b, rew_b, term_b, trunc_b, _) = (env.step(actions) for env in envs)
            assert not (term_a | trunc_a).any()
            torch.testing.assert_close(obs_a["policy"], obs_b["policy"], atol=1e-4, rtol=1e-4)
            torch.testing.assert_close(rew_a, rew_b, atol=1e-4, rtol=1e-4)
        for env in envs:
            env.close()
    finally:
        sys.modules.pop("isaaclab_inhand_env_cfg", None)
