"""Isaac Lab 3.0's tutorials (scripts/tutorials), written out under the 3.0 mapping in tests/ported3 (what
differs besides the imports at each file's top), run as a user runs them, headless on the CPU for a few
hundred app steps (``--max_app_steps``)."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest

PORTED3 = Path(__file__).parent / "ported3"
ROOT = Path(__file__).parent.parent


def _run(script: str, steps: int, *args: str) -> str:
    argv = [sys.executable, str(PORTED3 / script), "--headless", "--device", "cpu", "--max_app_steps", str(steps)]
    done = subprocess.run([*argv, *args], capture_output=True, text=True, timeout=300, cwd=ROOT)
    assert done.returncode == 0, done.stdout[-2000:] + done.stderr[-2000:]
    assert "Setup complete" in done.stdout
    return done.stdout


def test_create_empty_steps_until_the_app_stops():
    _run("create_empty.py", 10)


def test_run_rigid_object_drops_the_cones_onto_the_ground():
    out = _run("run_rigid_object.py", 251)
    assert out.count("Resetting object state") == 2  # steps 0 and 250
    # the last position printed before the second reset (step 250): four cones resting on the ground,
    # each within the cylinder's 0.1 m of its origin
    rows = re.findall(r"\[\s*(-?[\d.]+),\s*(-?[\d.]+),\s*(-?[\d.]+)\]", out.split("Root position")[-1])
    assert len(rows) == 4
    origins = [(0.25, 0.25), (-0.25, 0.25), (0.25, -0.25), (-0.25, -0.25)]
    for (x, y, z), (ox, oy) in zip(rows, origins):
        assert float(z) == pytest.approx(0.1, abs=0.01)  # at rest on the plane: half its 0.2 m height up
        assert ((float(x) - ox) ** 2 + (float(y) - oy) ** 2) ** 0.5 < 0.1 + 0.05


def test_create_scene_instantiates_a_3_0_scene_and_drives_it():
    out = _run("create_scene.py", 501, "--num_envs", "4")
    assert out.count("Resetting robot state") == 2  # steps 0 and 500


def test_run_diff_ik_reaches_its_x_y_z_w_goals():
    """Its goals are (x, y, z, qx, qy, qz, qw): the hand reaches each (the controller, the markers and the
    math read 3.0's order; read as (w, x, y, z) the goals would be other rotations and the errors large)."""
    out = _run("run_diff_ik.py", 451, "--num_envs", "2")
    errors = re.findall(r"Goal error: position ([\d.]+) m, orientation ([\d.]+) rad", out)
    assert len(errors) == 3  # the three goals, each left at steps 150, 300 and 450
    for position, orientation in errors:
        assert float(position) < 0.01 and float(orientation) < 0.02
