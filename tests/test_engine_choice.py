"""``SimulationCfg.engine``: which physics steps the worlds, and MuJoCo Warp on the CPU.

MuJoCo Warp runs on Warp's CPU device too (slowly). Running a task there with the same actions as
on MuJoCo C checks the GPU path's code (the cuda backend, its data views and resets) on a machine
without a GPU; the two engines integrate the same equations, so a contact-free task's trajectories
agree to float32 precision.
"""

from __future__ import annotations

import gymnasium as gym
import mujoco
import pytest
import torch

import simlab.tasks  # noqa: F401 - registers the tasks
from simlab.sim.backends import CpuBackend, make_backend
from simlab.tasks.utils import parse_env_cfg

CARTPOLE_XML = "simlab/robots/assets/cartpole.xml"


def _warp_on_cpu() -> str | None:
    try:
        import mujoco_warp  # noqa: F401
        import warp  # noqa: F401
    except ImportError as err:
        return f"mujoco-warp is not installed ({err}): pip install 'simlab[gpu]'"
    return None


needs_warp = pytest.mark.skipif(_warp_on_cpu() is not None, reason=str(_warp_on_cpu()))


def _trajectory(task: str, engine: str, steps: int = 30) -> tuple[torch.Tensor, str]:
    cfg = parse_env_cfg(task, device="cpu", num_envs=4)
    cfg.sim.engine = engine
    cfg.seed = 3
    env = gym.make(task, cfg=cfg).unwrapped
    try:
        obs, _ = env.reset(seed=3)
        frames = [obs["policy"].clone()]
        actions = torch.Generator().manual_seed(0)
        for _ in range(steps):
            action = torch.rand(4, env.single_action_space.shape[-1], generator=actions) * 2 - 1
            obs, *_ = env.step(action)
            frames.append(obs["policy"].clone())
        return torch.stack(frames), type(env.sim.backend).__name__
    finally:
        env.close()


@needs_warp
@pytest.mark.parametrize("task", ["simlab/Cartpole-v0", "simlab/Cartpole-Direct-v0", "simlab/Quadcopter-Direct-v0"])
def test_mujoco_warp_on_cpu_matches_mujoco(task):
    reference, backend = _trajectory(task, "auto")
    assert backend == "CpuBackend"
    warp, backend = _trajectory(task, "mujoco_warp")
    assert backend == "CudaBackend"
    assert reference.abs().max() > 0.1  # the cartpole moved: the comparison means something
    torch.testing.assert_close(warp, reference, atol=1e-4, rtol=0)


def test_engine_errors_name_the_choices():
    model = mujoco.MjModel.from_xml_path(CARTPOLE_XML)
    with pytest.raises(ValueError, match="'auto', 'mujoco', 'mujoco_warp'"):
        make_backend(model, 2, "cpu", engine="physx")
    with pytest.raises(ValueError, match="runs on the CPU only"):
        make_backend(model, 2, "cuda", engine="mujoco")
    assert isinstance(make_backend(model, 2, "cpu", engine="mujoco"), CpuBackend)
