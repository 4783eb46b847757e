"""MuJoCo Warp's fixed contact and constraint buffers: measured per task, and the AMP humanoid within them.

The AMP humanoid overflowed ``njmax`` on the GPU because its worlds blew up: its PD drives were
limited to 300 N m on every joint, and a drive at its limit leaves MuJoCo's implicit integration,
so light joints (a 0.5 kg foot) were flung from one limit to the other until the state diverged,
and a blown-up world has nearly every pair of geoms in contact. These tests run MuJoCo Warp's
kernels on Warp's CPU device (the GPU backend's code) and MuJoCo C (the same physics, fast).
"""

from __future__ import annotations

import gymnasium as gym
import mujoco
import pytest
import torch

import simlab.tasks  # noqa: F401 - registers the tasks
from simlab.sim.backends.buffer_peaks import BufferPeaks
from simlab.tasks.utils import parse_env_cfg
from simlab.tasks.utils.contact_buffers import measure_task_buffers

try:
    import mujoco_warp  # noqa: F401
    import warp  # noqa: F401

    WARP_MISSING = None
except ImportError as err:
    WARP_MISSING = f"mujoco-warp is not installed ({err}): pip install 'simlab[gpu]'"

needs_warp = pytest.mark.skipif(WARP_MISSING is not None, reason=str(WARP_MISSING))

AMP_WALK = "simlab/Humanoid-AMP-Walk-Direct-v0"

BOX_ON_PLANE = """
<mujoco>
  <option cone="pyramidal"/>
  <worldbody>
    <geom type="plane" size="5 5 0.1"/>
    <body name="box" pos="0 0 0.1">
      <freejoint/>
      <geom type="box" size="0.1 0.1 0.1" condim="3"/>
    </body>
  </worldbody>
</mujoco>
"""


@needs_warp
def test_buffer_peaks_count_contacts_and_rows_per_world():
    from simlab.sim.backends.cuda import CudaBackend

    model = mujoco.MjModel.from_xml_string(BOX_ON_PLANE)
    backend = CudaBackend(model, 2, device="cpu", nconmax=8, njmax=64)
    backend.data("qpos")[1, 2] = 5.0  # world 1's box is in the air: no contacts there
    backend.forward()
    peaks = BufferPeaks().watch(backend)
    backend.step(3)
    peaks.unwatch()
    assert peaks.samples == 1
    # a resting box touches the plane at its 4 corners; a pyramidal cone of condim 3 has 4 rows each
    assert peaks.contacts_per_world == 4
    assert peaks.constraint_rows == 16
    assert peaks.contacts_pooled == 2  # 4 contacts over 2 worlds sharing one pool
    backend.step(1)
    assert peaks.samples == 1  # unwatched: no more samples


def test_buffer_peaks_refuse_mujoco_c():
    from simlab.sim.backends import CpuBackend

    backend = CpuBackend(mujoco.MjModel.from_xml_string(BOX_ON_PLANE), 1)
    with pytest.raises(TypeError, match="engine='mujoco_warp'"):
        BufferPeaks().watch(backend)


def _diverged_worlds(effort_limit: float | None, num_envs: int = 32, steps: int = 100) -> int:
    """Worlds of the AMP humanoid that blew up under uniform random actions in [-1, 1] on MuJoCo C."""
    cfg = parse_env_cfg(AMP_WALK, device="cpu", num_envs=num_envs)
    cfg.seed = 1
    if effort_limit is not None:
        cfg.robot.actuators["body"].effort_limit_sim = effort_limit
    env = gym.make(AMP_WALK, cfg=cfg).unwrapped
    try:
        env.reset(seed=1)
        actions = torch.Generator().manual_seed(0)
        for _ in range(steps):
            env.step(torch.rand(num_envs, env.single_action_space.shape[-1], generator=actions) * 2 - 1)
        return int(env.sim.physics.diverged_count)
    finally:
        env.close()


def test_amp_humanoid_drives_are_stable_under_random_actions():
    assert _diverged_worlds(None) == 0
    # the limit it had when it overflowed on the GPU: the same rollout blows worlds up
    assert _diverged_worlds(300.0) > 0


@needs_warp
def test_amp_humanoid_steps_after_reference_resets_within_its_buffers():
    """The task's own buffers (headroom 1: an overflow raises), 1 s episodes: every env restarts
    from a reference state of the clip three times."""
    peaks, diverged, reserved = measure_task_buffers(
        AMP_WALK, num_envs=8, env_steps=90, headroom=1, episode_length_s=1.0
    )
    assert diverged == 0
    assert peaks.samples == 90 * 4
    assert peaks.contacts_per_world > 0  # the feet touch the ground: the count means something
    assert reserved["nconmax"] >= 2 * peaks.contacts_per_world
    assert reserved["njmax"] >= 2 * peaks.constraint_rows


@needs_warp
def test_lift_ik_rel_buffers_cover_its_peaks():
    peaks, diverged, reserved = measure_task_buffers(
        "simlab/Lift-Cube-Franka-IK-Rel-v0", num_envs=4, env_steps=40, headroom=1, episode_length_s=0.4
    )
    assert diverged == 0
    assert peaks.constraint_rows > 0
    assert reserved["nconmax"] >= 2 * peaks.contacts_per_world
    assert reserved["njmax"] >= 2 * peaks.constraint_rows
    # the solver converges in a few Newton iterations, far below the configured cap
    assert 1 <= peaks.solver_iterations < reserved["iterations"] == 100


@needs_warp
def test_the_former_amp_drives_overflow_and_the_error_says_worlds_diverged():
    """The GPU failure, on Warp's CPU device: 300 N m drives and 96 / 640 buffers (the config then)."""

    def former(cfg) -> None:
        cfg.robot.actuators["body"].effort_limit_sim = 300.0
        cfg.sim.mujoco.nconmax, cfg.sim.mujoco.njmax = 96, 640

    with pytest.raises(RuntimeError, match=r"nefc > njmax.*world\(s\) overflowed.*[1-9]\d* world\(s\) have diverged"):
        measure_task_buffers(AMP_WALK, num_envs=16, env_steps=100, headroom=1, episode_length_s=3.0, configure=former)


@pytest.mark.parametrize("motion", ["Walk", "Run", "Dance"])
def test_amp_reference_states_start_clear_of_the_ground_and_of_themselves(motion):
    """Reference-state initialisation puts no body into the ground or into another body (no contacts
    at all: the feet start ``reference_lift`` above the ground) and pushes no joint past its range."""
    task = f"simlab/Humanoid-AMP-{motion}-Direct-v0"
    env = gym.make(task, cfg=parse_env_cfg(task, device="cpu", num_envs=64)).unwrapped
    try:
        env.reset(seed=0)
        model, data = env.sim.model, mujoco.MjData(env.sim.model)
        limit_rows = 0
        for qpos in env.sim.physics.data("qpos").double().numpy():
            data.qpos[:] = qpos
            mujoco.mj_forward(model, data)
            assert data.ncon == 0, [mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_GEOM, c.geom1) for c in data.contact]
            limit_rows += int((data.efc_type[: data.nefc] == mujoco.mjtConstraint.mjCNSTR_LIMIT_JOINT).sum())
        assert limit_rows <= 64 // 16  # a clip's pose may touch a joint's limit, in a few envs at most
    finally:
        env.close()
