"""skrl on JAX (``--ml_framework jax`` / ``jax-numpy``) learns the cartpole on the CPU, without skrl's GPU warnings."""

from __future__ import annotations

import glob
import logging

import pytest

from simlab.cli.main import main

pytest.importorskip("flax", reason="skrl on JAX needs simlab[jax]")
pytest.importorskip("optax", reason="skrl on JAX needs simlab[jax]")


def _episode_lengths(run_dir: str) -> list[float]:
    from tensorboard.backend.event_processing.event_accumulator import EventAccumulator

    events = EventAccumulator(run_dir)
    events.Reload()
    return [s.value for s in events.Scalars("Episode / Total timesteps (mean)")]


@pytest.mark.slow  # a learning check: 70 iterations to balance the pole
@pytest.mark.parametrize("ml_framework", ["jax", "jax-numpy"])
def test_skrl_on_jax_learns_the_cartpole(tmp_path, caplog, ml_framework):
    argv = ["train", "--task", "simlab/Cartpole-v0", "--num_envs", "64", "--headless", "--device", "cpu"]
    argv += ["--library", "skrl", "--ml_framework", ml_framework, "--max_iterations", "70", "--seed", "42"]
    with caplog.at_level(logging.WARNING, logger="skrl"):
        assert main([*argv, "--log_root", str(tmp_path / "logs")]) == 0
    assert not [r.getMessage() for r in caplog.records if r.levelno >= logging.WARNING]  # no device warnings

    from skrl import config

    assert config.jax.backend == ("jax" if ml_framework == "jax" else "numpy")
    (run,) = glob.glob(str(tmp_path / "logs" / "skrl" / "*" / "*"))
    assert glob.glob(f"{run}/checkpoints/agent_*.pt")
    lengths = _episode_lengths(run)
    first, last = sum(lengths[:5]) / 5, sum(lengths[-5:]) / 5
    # a random policy drops the pole in ~25 steps; after 70 iterations it balances for 100+ (with the
    # jax 0.10.2, flax 0.12.8 and optax 0.2.8 installed on 2026-11-28 the episode length stalls near 70
    # steps from about iteration 10 to 45, then rises to the 300-step maximum; the 40 iterations this
    # test ran before, which passed CI on 2026-11-24, now end in the stall)
    assert first < 50 and last > 100, (first, last)


def test_ml_framework_is_for_skrl(tmp_path, capsys):
    argv = ["train", "--task", "simlab/Cartpole-v0", "--device", "cpu", "--ml_framework", "jax"]
    assert main([*argv, "--log_root", str(tmp_path / "logs")]) == 2
    assert "--ml_framework jax is skrl's; rsl_rl trains on torch" in capsys.readouterr().err
