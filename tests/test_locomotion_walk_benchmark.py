"""The rough-terrain measurement of scripts/benchmarks/locomotion_walk.py: envs start on the stairs
tiles it names, and a robot that gets past the last step counts as crossed, with its height change."""

from __future__ import annotations

import argparse
from pathlib import Path

import pytest
import torch
from conftest import load_script

from simlab.rl.rsl_rl import RslRlVecEnvWrapper

SCRIPT = Path(__file__).resolve().parents[1] / "scripts" / "benchmarks" / "locomotion_walk.py"


def _script():
    return load_script(SCRIPT)


def test_stairs_play_counts_robots_that_get_past_the_last_step(monkeypatch):
    walk = _script()
    args = argparse.Namespace(
        robot="go2", terrain="rough", device="cpu", seed=42, stairs_rows=[9], stairs_envs=1,
        stairs_speed=1.0, stairs_seconds=0.2, log_root="unused",
    )  # fmt: skip
    step = RslRlVecEnvWrapper.step
    calls = {"steps": 0, "origins": None}

    def step_and_carry_two_robots_out(self, actions):
        """After the 5th step, put env 0 (a pyramid: starts on top) and env 4 (an inverted pyramid:
        starts in the pit) on the flat border of their tiles, 3.5 m from the centre."""
        out = step(self, actions)
        calls["steps"] += 1
        env = self.unwrapped
        robot, origins = env.scene["robot"], env.scene.terrain.env_origins
        if calls["steps"] == 1:
            calls["origins"] = origins.clone()
        if calls["steps"] == 5:
            pose = robot.data.root_state_w[:, :7].clone()
            pose[[0, 4], 0] = origins[[0, 4], 0] + 3.5
            pose[[0, 4], 2] = 0.4  # the border is at ground level
            robot.write_root_pose_to_sim(pose)
        return out

    monkeypatch.setattr(RslRlVecEnvWrapper, "step", step_and_carry_two_robots_out)
    results = walk.play_stairs(lambda obs: torch.zeros(obs["policy"].shape[0], 12), args, None)

    # the 4 pyramid and the 4 inverted-pyramid columns of Isaac Lab's rough terrain, hardest row
    assert [(r["kind"], r["row"], r["envs"]) for r in results] == [
        ("pyramid_stairs", 9, 4),
        ("pyramid_stairs_inv", 9, 4),
    ]
    for r in results:
        assert 0.05 + 0.18 * 0.9 <= r["step_height"] <= 0.23  # step_height_range at difficulty >= 0.9
        assert r["crossed"] == pytest.approx(0.25) and r["falls"] == 0.0
    # the envs started on their tiles' platforms: 7 step heights above (or below) the ground
    z = calls["origins"][:, 2]
    assert bool((z[:4] > 1.4).all()) and bool((z[4:] < -1.4).all())
    down, up = results[0]["height_change"], results[1]["height_change"]
    assert down == pytest.approx(-7 * results[0]["step_height"], abs=0.15)
    assert up == pytest.approx(7 * results[1]["step_height"], abs=0.15)


def test_training_in_chunks_counts_each_iteration_once(tmp_path):
    """Rough training runs rsl_rl's ``learn`` once per curve point; the saved counter is the iterations run."""
    walk = _script()
    args = argparse.Namespace(
        robot="go2", terrain="rough", device="cpu", seed=42, num_envs=2, max_iterations=4, curve_every=2,
        train_seconds=None, log_root=str(tmp_path),
    )  # fmt: skip
    runner, _, curve = walk.train(args)
    assert [row[0] for row in curve] == [0, 2, 4]
    (final,) = tmp_path.glob("locomotion_walk/*/model_final.pt")
    assert torch.load(final, weights_only=False)["iter"] == 4
