"""scripts/tools/record_motion_clip.py: a clip recorded from a trained humanoid policy is a motion file
the AMP humanoid reads, and its velocities agree with its poses."""

from __future__ import annotations

import os

import gymnasium as gym
import numpy as np
import torch
from conftest import load_script

from simlab.tasks.direct.humanoid_amp.motions.motion_file import read_motion_file
from simlab.tasks.utils import parse_env_cfg

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def test_a_clip_recorded_from_the_shipped_humanoid_policy_drives_the_amp_env(tmp_path):
    script = load_script(os.path.join(REPO, "scripts", "tools", "record_motion_clip.py"))
    out = str(tmp_path / "run.npz")
    argv = ["--out", out, "--num_envs", "2", "--skip_seconds", "1", "--seconds", "1", "--log_root", str(tmp_path)]
    assert script.main(argv) == 0

    # stored as the root's and joints' states (the writer checked that forward kinematics, with the
    # root's velocities, gives the recorded body states back); read with the body states filled
    with np.load(out) as stored:
        assert "root_linear_velocities" in stored.files and "body_positions" not in stored.files
    clip = read_motion_file(out)
    fps = float(clip["fps"])
    assert fps == 60.0  # Humanoid-v0 steps at 1/120 s x 2
    assert clip["dof_positions"].shape == (60, 21)
    torso = list(clip["body_names"]).index("torso")
    position = clip["body_positions"][:, torso]
    # Humanoid-v0's policy runs towards +x at about 1.6 m/s, upright
    speed = (position[-1, 0] - position[0, 0]) * fps / (len(position) - 1)
    assert speed > 1.0 and position[:, 2].min() > 0.9
    # the recorded velocities are those of the recorded poses (central differences, one frame apart)
    finite = (position[2:] - position[:-2]) * fps / 2
    assert np.abs(finite - clip["body_linear_velocities"][1:-1, torso]).mean() < 0.1

    cfg = parse_env_cfg("simlab/Humanoid-AMP-Run-Direct-v0", device="cpu", num_envs=2)
    cfg.motion_file = out
    env = gym.make("simlab/Humanoid-AMP-Run-Direct-v0", cfg=cfg).unwrapped
    try:
        env.reset(seed=0)
        # reference-state initialisation puts the robot in a recorded pose
        height = env.robot.data.body_pos_w[:, env.ref_body_index, 2]
        assert torch.all(height > 0.9)
        reference = env.collect_reference_motions(8)
        assert reference.shape == (8, env.amp_observation_size) and torch.isfinite(reference).all()
    finally:
        env.close()
