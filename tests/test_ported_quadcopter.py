"""Isaac Lab's direct quadcopter task file, ported by the import mapping alone, runs on simlab.

``tests/ported/quadcopter_env.py`` is Isaac Lab's file with its ``isaaclab`` imports rewritten and
nothing else: it weighs the Crazyflie with ``root_physx_view.get_masses()``, pushes it through
``permanent_wrench_composer.set_forces_and_torques``, names ``envs.ui.BaseEnvWindow`` and draws its
goal with ``VisualizationMarkers``. The test steps it on the CPU and checks that it flies exactly as
simlab's own quadcopter task does under the same actions.
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

import numpy as np
import pytest
import torch
from conftest import DEVICES, load_script, rendering_available

from simlab.tasks.direct.quadcopter.quadcopter_env import QuadcopterEnv, QuadcopterEnvCfg

PORTED = Path(__file__).parent / "ported" / "quadcopter_env.py"
NUM_ENVS = 4
HOVER_THRUST = 2.0 / 1.9 - 1.0  # thrust_to_weight * weight * (a + 1) / 2 == weight


@pytest.fixture(scope="module")
def ported():
    yield load_script(PORTED, "isaaclab_quadcopter_env")
    sys.modules.pop("isaaclab_quadcopter_env", None)


def make(env_class, cfg_class, device: str = "cpu", **kwargs):
    cfg = cfg_class(seed=0)
    cfg.scene.num_envs = NUM_ENVS
    cfg.sim.device = device
    return env_class(cfg, **kwargs)


def test_only_import_lines_name_simlab():
    code = [line for line in PORTED.read_text().splitlines() if line and not line.startswith("#")]
    assert not any("isaaclab" in line for line in code)
    simlab_lines = [line for line in code if "simlab" in line]
    assert len(simlab_lines) == 12
    assert all(re.match(r"(from|import) simlab", line) for line in simlab_lines), simlab_lines


def fly(env, num_steps: int = 50) -> tuple[torch.Tensor, torch.Tensor]:
    """Body-frame velocities and gravity (the goals are drawn differently), and root states, over
    ``num_steps`` steps of hover thrust with small random moments."""
    env.reset()
    env.episode_length_buf.zero_()  # a full episode ahead: no time-out inside the test
    generator = torch.Generator().manual_seed(0)
    observed, states = [], []
    for _ in range(num_steps):
        action = torch.zeros(NUM_ENVS, 4, device=env.device)
        action[:, 0] = HOVER_THRUST
        action[:, 1:] = 0.01 * (2 * torch.rand(NUM_ENVS, 3, generator=generator) - 1).to(env.device)
        obs, _, terminated, truncated, _ = env.step(action)
        assert not (terminated | truncated).any()
        observed.append(obs["policy"][:, :9].cpu())
        states.append(env._robot.data.root_state_w.cpu())
    return torch.stack(observed), torch.stack(states)


@pytest.mark.parametrize("device", DEVICES)
def test_ported_file_flies_as_simlab_s_own_quadcopter(ported, device):
    env = make(ported.QuadcopterEnv, ported.QuadcopterEnvCfg, device)
    try:
        masses = env._robot.root_physx_view.get_masses()
        assert masses.shape == (NUM_ENVS, env._robot.num_bodies) and masses.device.type == "cpu"
        assert masses[0].sum().item() == pytest.approx(0.027, rel=1e-6)  # the Crazyflie's published mass
        weight = env._robot_weight
        observed, states = fly(env)
        composer = env._robot.permanent_wrench_composer
        assert composer.active
        torch.testing.assert_close(composer.composed_force[:, 0, 2].cpu(), torch.full((NUM_ENVS,), weight))
    finally:
        env.close()
    # the thrust holds the weight: tilted by the small moments it sinks by cm (free fall: 4.9 m in 1 s)
    assert (states[:, :, 2] - states[0, :, 2]).abs().max() < 0.1
    native = make(QuadcopterEnv, QuadcopterEnvCfg, device)
    try:
        assert native._robot_weight == pytest.approx(weight)
        native_observed, native_states = fly(native)
    finally:
        native.close()
    # the same physics: bit for bit on the CPU; on the GPU the native task's step is one CUDA graph
    tolerance = {} if device == "cpu" else {"atol": 1e-4, "rtol": 1e-4}
    torch.testing.assert_close(observed, native_observed, **tolerance)
    torch.testing.assert_close(states, native_states, **tolerance)


@pytest.mark.skipif(not rendering_available(), reason="needs offscreen rendering (EGL or OSMesa)")
def test_goal_marker_is_drawn_in_renders(ported):
    cfg = ported.QuadcopterEnvCfg(seed=0)
    cfg.scene.num_envs = 1
    cfg.sim.device = "cpu"
    cfg.viewer.eye, cfg.viewer.lookat = (1.5, -1.5, 1.0), (0.0, 0.0, 0.6)
    env = ported.QuadcopterEnv(cfg, render_mode="rgb_array")
    try:
        assert env.has_debug_vis_implementation and cfg.debug_vis
        env.reset()
        env._desired_pos_w[:] = torch.tensor([0.0, 0.0, 0.6])  # in view, above the drone
        with_goal = env.render()
        assert env.set_debug_vis(False)
        without_goal = env.render()
        changed = np.any(with_goal != without_goal, axis=-1)
        assert changed.sum() > 50, "the 5 cm goal cube covers some pixels"
        red = with_goal[changed].astype(int)
        assert (red[:, 0] > red[:, 1] + 40).mean() > 0.5, "the changed pixels are the red cube's"
    finally:
        env.close()


@pytest.mark.parametrize("engine", ["mujoco", pytest.param("mujoco_warp", marks=pytest.mark.slow)])
def test_set_masses_changes_the_dynamics(ported, engine):
    """Double the mass of env 1 through PhysX's view names: the thrust that holds env 0's weight lets
    it sink at g / 2 (0.981 m/s after 0.2 s); ``mujoco_warp`` runs the GPU backend's code on the CPU."""
    cfg = ported.QuadcopterEnvCfg(seed=0)
    cfg.scene.num_envs = 2
    cfg.sim.device, cfg.sim.engine = "cpu", engine
    env = ported.QuadcopterEnv(cfg)
    try:
        view = env._robot.root_physx_view
        masses = view.get_masses()
        masses[1] *= 2.0
        view.set_masses(masses, torch.tensor([1]))
        assert view.get_masses().sum(dim=1).tolist() == pytest.approx([0.027, 0.054])
        env.reset()
        env.episode_length_buf.zero_()
        hover = torch.tensor([[HOVER_THRUST, 0.0, 0.0, 0.0]] * 2)
        for _ in range(10):  # 0.2 s
            env.step(hover)
        vz = env._robot.data.root_lin_vel_w[:, 2].tolist()
        assert vz == pytest.approx([0.0, -9.81 / 2 * 0.2], abs=1e-4)
    finally:
        env.close()
