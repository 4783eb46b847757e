"""scripts/benchmarks/manipulation_learn.py end to end on the CPU: a training stopped by its time
budget saves a checkpoint, and the evaluation plays that checkpoint and judges it."""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
SCRIPT = ROOT / "scripts" / "benchmarks" / "manipulation_learn.py"


@pytest.mark.slow  # a 30 s training budget, then its evaluation
def test_lift_training_stopped_by_its_budget_is_evaluated_from_its_checkpoint(tmp_path):
    args = ["--tasks", "lift", "--device", "cpu", "--num_envs", "4", "--max_iterations", "100000"]
    args += ["--train_budget_s", "30", "--eval_envs", "2", "--eval_seconds", "5.1", "--log_root", str(tmp_path)]
    result = subprocess.run(
        [sys.executable, str(SCRIPT), *args],
        capture_output=True, text=True, timeout=300, cwd=ROOT, env=dict(os.environ, PYTHONUNBUFFERED="1"),
    )  # fmt: skip
    out = result.stdout + result.stderr
    assert "training budget of 30 s reached: stopping it" in out, out[-3000:]
    evaluated = re.search(r"=== evaluating (\S+model_(\d+)\.pt)", out)
    assert evaluated and Path(evaluated[1]).is_file(), out[-3000:]
    assert int(evaluated[2]) < 100000  # stopped long before max_iterations
    # a 5 s episode per eval env (and any ended by the cube falling off the table) is judged;
    # an untrained policy lifts no cube
    assert re.search(r"simlab/Lift-Cube-Franka-v0 +\d+\.\d +FAIL: 0/[2-9] episodes within 5 cm", out), out[-3000:]
    assert result.returncode == 1
