"""An env count that cannot fit is refused in one line before anything of its size is made (issue 37,
item 7): the physics backend checks the memory first thing in ``sim.reset()``, and what is as large
as the env count (env origins, terrain levels, event timers, episode lengths) is made after it."""

from __future__ import annotations

import os
import resource
from contextlib import contextmanager

import gymnasium as gym
import mujoco
import pytest
import torch

import simlab.sim.backends.cpu as cpu
import simlab.tasks  # noqa: F401  (registers the tasks)
from simlab.cli.main import main
from simlab.tasks.utils import parse_env_cfg
from simlab.terrains.terrain_importer import grid_origins
from simlab.utils.errors import ConfigError

HUGE = 10**9  # any tensor of this many rows is at least 1 GB, far past the headroom below
HEADROOM = 512 * 2**20


def _mapped_bytes() -> int:
    with open("/proc/self/status") as f:
        return next(int(line.split()[1]) * 1024 for line in f if line.startswith("VmSize:"))


@contextmanager
def _no_large_allocation(headroom: int = HEADROOM):
    """Within the block this process can map at most ``headroom`` more bytes (RLIMIT_AS): a larger
    allocation fails with an error of its own instead of the refusal."""
    soft, hard = resource.getrlimit(resource.RLIMIT_AS)
    resource.setrlimit(resource.RLIMIT_AS, (_mapped_bytes() + headroom, hard))
    try:
        yield
    finally:
        resource.setrlimit(resource.RLIMIT_AS, (soft, hard))


needs_proc = pytest.mark.skipif(not os.path.exists("/proc/self/status"), reason="reads the mapped memory from /proc")


@needs_proc
@pytest.mark.parametrize("task", ["simlab/Cartpole-v0", "simlab/Cartpole-Direct-v0"])
def test_train_refuses_an_env_count_that_cannot_fit_before_allocating_it(tmp_path, capsys, monkeypatch, task):
    monkeypatch.setattr(cpu, "available_memory", lambda: 2**30)
    argv = ["train", "--task", task, "--num_envs", str(HUGE), "--headless", "--device", "cpu", "--max_iterations", "1"]
    with _no_large_allocation():
        code = main([*argv, "--log_root", str(tmp_path / "logs")])
    err = capsys.readouterr().err
    assert code == 2, err
    assert "Traceback" not in err and len(err.strip().splitlines()) == 1, err
    assert f"simlab train: error: {HUGE} envs need about " in err
    assert "(6.4 KiB per env for this model), but 1.0 GiB is available: at most about " in err
    fits = int(err.split("at most about ")[1].split()[0])
    assert 0 < fits < 2**30 // 6592  # one cartpole MjData is 6592 bytes; the worker threads' arenas come off


@needs_proc
def test_a_generated_terrain_places_its_envs_after_the_check(monkeypatch):
    """The terrain's per-env state (levels, columns, origins) is made on first read, after the check."""
    monkeypatch.setattr(cpu, "available_memory", lambda: 2**30)
    made = []
    monkeypatch.setattr(
        "simlab.terrains.terrain_importer.TerrainImporter._configure_curriculum_origins",
        lambda self: made.append(self.cfg.num_envs),
    )
    cfg = parse_env_cfg("simlab/Velocity-Rough-Anymal-C-v0", device="cpu", num_envs=HUGE)
    with _no_large_allocation(), pytest.raises(ConfigError, match=f"^{HUGE} envs need about .* envs fit"):
        gym.make("simlab/Velocity-Rough-Anymal-C-v0", cfg=cfg)
    assert not made


def test_an_env_count_that_fits_gets_its_origins(monkeypatch):
    monkeypatch.setattr(cpu, "available_memory", lambda: 2**30)
    cfg = parse_env_cfg("simlab/Cartpole-v0", device="cpu", num_envs=5)
    env = gym.make("simlab/Cartpole-v0", cfg=cfg)
    try:
        scene = env.unwrapped.scene
        assert torch.equal(scene.env_origins, grid_origins(5, cfg.scene.env_spacing, "cpu"))
        assert scene.env_origins is env.unwrapped.sim.env_origins  # one tensor, made once
        env.reset(seed=0)
        obs, *_ = env.step(torch.zeros(5, 1))
        assert obs["policy"].shape[0] == 5
    finally:
        env.close()


# --- MuJoCo Warp: its data per world, measured on Warp's CPU device ------------------------------


def _cartpole_model() -> mujoco.MjModel:
    return mujoco.MjModel.from_xml_string(
        """<mujoco><worldbody><body><joint name="slide" type="slide"/><geom size="0.1" mass="1"/>
        <body><joint type="hinge" axis="0 1 0" range="-1 1"/><geom type="capsule" fromto="0 0 0 0 0 1" size="0.05"/>
        </body></body></worldbody></mujoco>"""
    )


def test_the_warp_data_estimate_is_what_put_data_allocates():
    pytest.importorskip("mujoco_warp")
    from simlab.sim.backends.cuda import _array_bytes, require_cuda_backend, warp_data_bytes

    wp, mjw = require_cuda_backend("cpu")
    model = _cartpole_model()
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    per_world, fixed = warp_data_bytes(wp, mjw, model, data, nconmax=None, njmax=None)
    assert per_world > data.nbuffer // 4  # MuJoCo Warp holds (less than) one MjData's arrays per world
    with wp.ScopedDevice("cpu"):
        for nworld in (3, 5):
            allocated = _array_bytes(mjw.put_data(model, data, nworld=nworld))
            assert allocated == nworld * per_world + fixed


def test_the_cuda_backend_refuses_worlds_its_gpu_cannot_hold():
    """The check ``CudaBackend`` runs before ``put_data``, with a faked free GPU memory (no GPU here)."""
    pytest.importorskip("mujoco_warp")
    from simlab.sim.backends.cuda import check_warp_memory, require_cuda_backend, warp_data_bytes

    wp, mjw = require_cuda_backend("cpu")
    model = _cartpole_model()
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    per_world, fixed = warp_data_bytes(wp, mjw, model, data, 0, 2)
    free = 10 * 2**30
    fits = (free - fixed) // per_world
    check_warp_memory(wp, mjw, model, data, fits, 0, 2, free, "cuda:0")  # the most that fit: no error
    with pytest.raises(ConfigError) as err:
        check_warp_memory(wp, mjw, model, data, fits + 1, 0, 2, free, "cuda:0")
    message = str(err.value)
    assert "\n" not in message
    assert message.startswith(f"{fits + 1} envs need about 10.0 GiB of GPU memory for MuJoCo Warp on cuda:0 (")
    assert message.endswith(
        f"but 10.0 GiB is available: at most about {fits} envs fit (--num_envs or env.scene.num_envs)."
    )


def test_mujoco_warp_on_the_cpu_refuses_before_put_data(monkeypatch):
    """End to end through ``make_backend`` (MuJoCo Warp's CPU device checks the host's memory)."""
    pytest.importorskip("mujoco_warp")
    import simlab.sim.backends.cuda as cuda
    from simlab.sim.backends import make_backend

    monkeypatch.setattr(cuda, "available_memory", lambda: 2**30)
    model = _cartpole_model()
    with _no_large_allocation(), pytest.raises(ConfigError, match=f"^{HUGE} envs need .* of memory for MuJoCo Warp"):
        make_backend(model, HUGE, "cpu", engine="mujoco_warp")
    backend = make_backend(model, 4, "cpu", engine="mujoco_warp")
    assert backend.num_envs == 4
