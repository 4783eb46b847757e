"""scripts/benchmarks/velocity_error_breakdown.py: windowed errors separate sway from tracking."""

from __future__ import annotations

import os

import torch
from conftest import load_script

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def test_a_base_that_sways_about_the_command_has_a_small_windowed_error():
    script = load_script(os.path.join(REPO, "scripts", "benchmarks", "velocity_error_breakdown.py"))
    steps = torch.arange(100, dtype=torch.float32)
    commands = torch.zeros(100, 3, 2)
    commands[..., 0] = 1.0
    velocities = commands.clone()
    velocities[..., 0] += 0.2 * torch.sin(2 * torch.pi * steps / 10).unsqueeze(-1)  # 10-step sway
    instantaneous = float((commands - velocities).norm(dim=-1).mean())
    assert 0.12 < instantaneous < 0.13  # 0.2 * mean |sin| = 0.2 * 2 / pi
    assert script.windowed_error(commands, velocities, 1) == instantaneous
    assert script.windowed_error(commands, velocities, 10) < 1e-6  # whole sway periods average out
    velocities[..., 0] -= 0.3  # 0.3 m/s too slow: no window hides that
    assert abs(script.windowed_error(commands, velocities, 10) - 0.3) < 1e-5
