"""scripts/benchmarks/amp_discriminator_probe.py: a discriminator with skrl AMP's losses tells the
simulated humanoid from a clip whose torso is pinned upright (zero angular velocity, the former
shipped clips) by the torso's angular velocity alone, and much less so from the shipped walk clip."""

from __future__ import annotations

import dataclasses
import os

import gymnasium as gym
from conftest import load_script

from simlab.tasks.direct.humanoid_amp.humanoid_amp_env_cfg import AMP_OBSERVATION_SIZE, KEY_BODIES, NUM_JOINTS
from simlab.tasks.direct.humanoid_amp.motions.kinematic_clips import CLIPS, make_clip
from simlab.tasks.direct.humanoid_amp.motions.motion_file import write_motion_file
from simlab.tasks.utils import load_cfg_from_registry

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TASK = "simlab/Humanoid-AMP-Walk-Direct-v0"


def _probe():
    return load_script(os.path.join(REPO, "scripts", "benchmarks", "amp_discriminator_probe.py"))


def _sim_score_by_angular_velocity(probe, motion_file: str | None) -> float:
    cfg = load_cfg_from_registry(TASK, "env_cfg_entry_point")
    cfg.scene.num_envs, cfg.sim.device, cfg.seed = 32, "cpu", 0
    if motion_file:
        cfg.motion_file = motion_file
    env = gym.make(TASK, cfg=cfg)
    try:
        fake, real = probe.collect(env, steps=6, episodes=2)
    finally:
        env.close()
    columns = probe.feature_columns(NUM_JOINTS, len(KEY_BODIES))["ang_vel"]
    columns = columns + [c + AMP_OBSERVATION_SIZE for c in columns]  # both frames of the history
    return probe.discriminator_score(fake[:, columns], real[:, columns], iterations=300, seed=0)[1]


def test_a_pinned_torso_gives_the_sim_away(tmp_path):
    probe = _probe()
    columns = probe.feature_columns(NUM_JOINTS, len(KEY_BODIES))
    assert sorted(c for group in columns.values() for c in group) == list(range(AMP_OBSERVATION_SIZE))
    pinned = dataclasses.replace(CLIPS["walk"], torso_sway=lambda phase: (0.0, 0.0, 0.0))
    clip, _ = make_clip(pinned)
    write_motion_file(str(tmp_path / "pinned.npz"), **clip)
    d_pinned = _sim_score_by_angular_velocity(probe, str(tmp_path / "pinned.npz"))
    d_shipped = _sim_score_by_angular_velocity(probe, None)
    assert d_pinned < 0.15 and d_shipped > 2 * d_pinned, (d_pinned, d_shipped)  # measured: 0.10, 0.34
