"""Isaac Lab's Shadow Hand task config, ported by the import mapping alone, runs on simlab.

``tests/ported/shadow_hand_env_cfg.py`` is Isaac Lab's file with its ``isaaclab`` imports rewritten
and nothing else. Its ``ShadowHandEnvCfg`` runs in Isaac Lab's own ``inhand_manipulation_env.py``
(ported beside it); its ``ShadowHandOpenAIEnvCfg`` (noise models, domain randomization with the fixed
tendon term, the asymmetric critic) runs in simlab's in-hand env, which compiles in the MuJoCo pass that
the fingertip wrenches need, and in Isaac Lab's, which asks PhysX's articulation view for them (the
backend then runs that pass when they are read). The OpenAI config holds the same settings as simlab's
registered one.
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

import pytest
import torch
from conftest import load_script

from simlab.tasks.direct.inhand_manipulation.inhand_manipulation_env import InHandManipulationEnv
from simlab.tasks.direct.shadow_hand.shadow_hand_env_cfg import ShadowHandEnvCfg, ShadowHandOpenAIEnvCfg

PORTED = Path(__file__).parent / "ported"
NUM_ENVS = 4


@pytest.fixture(scope="module")
def ported():
    cfg_module = load_script(PORTED / "shadow_hand_env_cfg.py", "isaaclab_shadow_hand_env_cfg")
    env_module = load_script(PORTED / "inhand_manipulation_env.py", "isaaclab_inhand_manipulation_env")
    yield cfg_module, env_module
    for name in ("isaaclab_shadow_hand_env_cfg", "isaaclab_inhand_manipulation_env"):
        sys.modules.pop(name, None)


def test_only_import_lines_name_simlab():
    code = [line for line in (PORTED / "shadow_hand_env_cfg.py").read_text().splitlines() if line and line[0] != "#"]
    assert not any("isaaclab" in line for line in code)
    simlab_lines = [line.strip() for line in code if "simlab" in line]
    assert simlab_lines and all(re.match(r"(from|import) simlab", line) for line in simlab_lines), simlab_lines


def make(env_class, cfg, device: str = "cpu"):
    cfg.seed = 0
    cfg.scene.num_envs = NUM_ENVS
    cfg.sim.device = device
    cfg.sim.mujoco = ShadowHandEnvCfg().sim.mujoco  # simlab's MuJoCo settings for the task
    return env_class(cfg)


def run(env, steps: int = 20) -> dict:
    obs, _ = env.reset(seed=0)
    generator = torch.Generator().manual_seed(0)
    for _ in range(steps):
        actions = 0.5 * (2 * torch.rand(NUM_ENVS, 20, generator=generator) - 1)
        obs, reward, *_ = env.step(actions.to(env.device))
        assert all(torch.isfinite(group).all() for group in obs.values()) and torch.isfinite(reward).all()
    return obs


def test_ported_shadow_task_steps_in_isaac_lab_s_env(ported):
    cfg_module, env_module = ported
    env = make(env_module.InHandManipulationEnv, cfg_module.ShadowHandEnvCfg())
    try:
        assert env.object.data.default_mass[0].item() == pytest.approx(567.0 * 0.06**3, rel=1e-4)
        assert run(env)["policy"].shape == (NUM_ENVS, 157)
    finally:
        env.close()


def test_ported_openai_config_runs_and_matches_simlab_s(ported):
    cfg_module, _ = ported
    ported_cfg, own_cfg = cfg_module.ShadowHandOpenAIEnvCfg(), ShadowHandOpenAIEnvCfg()
    for field in ("decimation", "episode_length_s", "observation_space", "state_space", "obs_type",
                  "success_tolerance", "fall_penalty", "max_consecutive_success", "act_moving_average"):  # fmt: skip
        assert getattr(ported_cfg, field) == getattr(own_cfg, field), field
    assert ported_cfg.sim.dt == own_cfg.sim.dt
    assert ported_cfg.action_noise_model.to_dict() == own_cfg.action_noise_model.to_dict()
    assert ported_cfg.observation_noise_model.to_dict() == own_cfg.observation_noise_model.to_dict()
    ported_events, own_events = ported_cfg.events.to_dict(), own_cfg.events.to_dict()
    assert ported_events.keys() == own_events.keys()
    for name, term in ported_events.items():
        assert term["params"] == own_events[name]["params"], name
    env = make(InHandManipulationEnv, ported_cfg)
    try:
        obs = run(env)
        assert obs["policy"].shape == (NUM_ENVS, 42) and obs["critic"].shape == (NUM_ENVS, 187)
    finally:
        env.close()


def test_isaac_lab_s_env_reads_physx_s_joint_forces_for_its_critic(ported):
    """Isaac Lab's env with the OpenAI config reads PhysX's incoming joint forces for its critic
    (``root_physx_view.get_link_incoming_joint_force()``) and nothing turns MuJoCo's post-constraint
    pass on before the model compiles: the backend runs the pass when they are read. The fingertip
    wrenches in the critic's state are those simlab's asset data give."""
    cfg_module, env_module = ported
    env = make(env_module.InHandManipulationEnv, cfg_module.ShadowHandOpenAIEnvCfg())
    try:
        obs = run(env, steps=10)
        assert obs["policy"].shape == (NUM_ENVS, 42) and obs["critic"].shape == (NUM_ENVS, 187)
        tips = env.hand.data.body_incoming_joint_wrench_b[:, env.finger_bodies].reshape(NUM_ENVS, -1)
        torch.testing.assert_close(env.fingertip_force_sensors.reshape(NUM_ENVS, -1), tips)
        assert tips.abs().amax() > 1e-3  # the fingers touch the cube
    finally:
        env.close()


@pytest.mark.gpu
def test_isaac_lab_s_env_reads_the_joint_forces_on_the_gpu(ported):
    """On MuJoCo Warp the pass is one launch when read (Isaac Lab's env resets by ids: its step runs eagerly)."""
    cfg_module, env_module = ported
    env = make(env_module.InHandManipulationEnv, cfg_module.ShadowHandOpenAIEnvCfg(), device="cuda:0")
    try:
        obs = run(env, steps=10)
        read = env.fingertip_force_sensors.clone()  # what the last step's critic read
        again = env.hand.data.body_incoming_joint_wrench_b[:, env.finger_bodies]  # the same state, read again
        torch.testing.assert_close(read, again, atol=1e-4, rtol=1e-4)
        assert again.abs().amax() > 1e-3 and obs["critic"].shape == (NUM_ENVS, 187)
    finally:
        env.close()


@pytest.mark.gpu
def test_the_pass_run_when_read_is_recorded_into_the_captured_env_step():
    """simlab's in-hand env, which resets by mask, replays its step as one CUDA graph. Built with the pass
    left out of the model (as Isaac Lab's env leaves it), the launch made when its critic reads the
    forces is recorded into that graph: each replay gives the forces of its own state."""
    from unittest import mock

    import simlab.sim as sim_utils
    from simlab.sim.backends.base import runs_post_constraint

    with mock.patch.object(sim_utils, "compute_body_interaction_forces"):  # the env's _setup_scene calls it
        env = make(InHandManipulationEnv, ShadowHandOpenAIEnvCfg(), device="cuda:0")
    try:
        assert not runs_post_constraint(env.sim.model)  # nothing makes MuJoCo Warp's forward run the pass
        run(env, steps=10)  # warm-up, capture, replays
        assert env._stepper.is_graphed, env._stepper.mode
        replayed = env.fingertip_force_sensors.clone()  # what the last replay's critic read
        eager = env.hand.data.body_incoming_joint_wrench_b[:, env._tips]  # run again now, at the same state
        torch.testing.assert_close(replayed, eager, atol=1e-4, rtol=1e-4)
        assert eager.abs().amax() > 1e-3
    finally:
        env.close()
