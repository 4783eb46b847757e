"""Isaac Lab's own tutorial scripts, those docs/tutorials.md says run, run after the import mapping.

simlab's ``scripts/tutorials`` are scripts written here that make the same calls (tests/test_tutorials.py
runs them in CI). This file runs Isaac Lab's own text: each tutorial of an Isaac Lab 2.x checkout
(``scripts/tutorials/<folder>/<name>.py``), its import lines mapped as the README says (the mapping of
tests/test_isaaclab_task_files.py), headless on the CPU, bounded by ``SIMLAB_MAX_APP_STEPS``; it must
exit 0. Isaac Lab's files are not kept here: ``SIMLAB_ISAACLAB_SOURCE`` names the checkout, as for the
task files, and without it the cases skip (a tutorial the checkout lacks skips too). A tutorial the
page says is refused must stop at a one-line error saying why.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest
from test_isaaclab_task_files import SOURCE, port_line

ROOT = Path(__file__).resolve().parents[1]

TUTORIALS = dict(re.findall(r"^\| `([\w/]+\.py)` \| ([^|]+?) \|", (ROOT / "docs" / "tutorials.md").read_text(), re.M))
"""docs/tutorials.md's rows: Isaac Lab's tutorial -> simlab's status ("runs", "refused: ...")."""

ARGS = {  # a few envs where the script takes --num_envs; cameras where it renders
    "02_scene/create_scene.py": ["--num_envs", "2"],
    "03_envs/create_cartpole_base_env.py": ["--num_envs", "2"],
    "03_envs/create_cube_base_env.py": ["--num_envs", "2"],
    "03_envs/create_quadruped_base_env.py": ["--num_envs", "2"],
    "03_envs/run_cartpole_rl_env.py": ["--num_envs", "2"],
    "03_envs/policy_inference_in_usd.py": ["--checkpoint", "policy.pt"],  # a required flag
    "04_sensors/add_sensors_on_robot.py": ["--num_envs", "2", "--enable_cameras"],
    "04_sensors/run_ray_caster_camera.py": ["--enable_cameras"],
    "04_sensors/run_usd_camera.py": ["--enable_cameras"],
    "05_controllers/run_diff_ik.py": ["--num_envs", "2"],
    "05_controllers/run_osc.py": ["--num_envs", "2"],
}
STEPS = {"04_sensors/run_ray_caster_camera.py": 3, "04_sensors/run_usd_camera.py": 3}  # 640 x 480 images
LEFT_OUT = {"00_sim/spawn_prims.py": ("deformable_props=", "=sim_utils.DeformableBodyMaterialCfg()")}
"""Lines left out of a tutorial (those containing one of the texts), as docs/tutorials.md says: the
cuboid's ``deformable_props`` and deformable material ask for a PhysX soft body, which simlab refuses in
one line (its bodies are rigid)."""


def run_isaac_labs_tutorial(name: str, folder: Path) -> subprocess.CompletedProcess:
    """Isaac Lab's ``scripts/tutorials/<name>``, mapped (less the lines of :data:`LEFT_OUT`) into
    ``folder`` and run there headless on the CPU (the tutorials write beside themselves or below the cwd)."""
    source = Path(SOURCE) / "scripts" / "tutorials" / name
    if not source.is_file():
        pytest.skip(f"this Isaac Lab checkout has no scripts/tutorials/{name}")
    script = folder / source.name
    lines = source.read_text().splitlines(keepends=True)
    lines = [line for line in lines if not any(text in line for text in LEFT_OUT.get(name, ()))]
    script.write_text("".join(port_line(line, "unused", ()) for line in lines))
    env = dict(os.environ, PYTHONUNBUFFERED="1", SIMLAB_MAX_APP_STEPS=str(STEPS.get(name, 40)))
    return subprocess.run(
        [sys.executable, str(script), "--headless", "--device", "cpu", *ARGS.get(name, [])],
        capture_output=True, text=True, timeout=300, env=env, cwd=folder,
    )  # fmt: skip


@pytest.mark.skipif(not SOURCE, reason="SIMLAB_ISAACLAB_SOURCE (an Isaac Lab 2.x checkout) is not set")
@pytest.mark.parametrize("name", sorted(name for name, status in TUTORIALS.items() if status == "runs"))
def test_isaac_labs_tutorial_runs_after_the_import_mapping(name, tmp_path):
    result = run_isaac_labs_tutorial(name, tmp_path)
    assert result.returncode == 0, result.stdout[-2000:] + result.stderr[-2000:]


@pytest.mark.skipif(not SOURCE, reason="SIMLAB_ISAACLAB_SOURCE (an Isaac Lab 2.x checkout) is not set")
@pytest.mark.parametrize("name", sorted(name for name, status in TUTORIALS.items() if status.startswith("refused")))
def test_isaac_labs_refused_tutorial_stops_at_one_line_saying_why(name, tmp_path):
    """A refused tutorial ends with simlab's one-line error (a USD asset, a soft body), or, where it
    needs Kit itself, Python's own line that there is no ``omni`` module; never another traceback."""
    result = run_isaac_labs_tutorial(name, tmp_path)
    last = result.stderr.strip().splitlines()[-1]
    allowed = r"simlab\.utils\.errors\.\w+: " + (
        r"|ModuleNotFoundError: No module named 'omni'" if "Kit" in TUTORIALS[name] else ""
    )
    assert result.returncode != 0 and re.match(allowed, last), result.stderr[-2000:]
