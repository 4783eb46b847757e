"""scripts/benchmarks/lift_error_breakdown.py on the shipped lift policy: it says what the criterion says."""

from __future__ import annotations

import os
import re
import shutil

from conftest import load_script

from simlab.pretrained import copy_pretrained_run

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def test_the_shipped_lift_policy_ends_lifted_and_at_its_goal(tmp_path, capsys):
    script = load_script(os.path.join(REPO, "scripts", "benchmarks", "lift_error_breakdown.py"))
    # the shipped run folder as a training run of the user's (play's --use_last_checkpoint finds it)
    run = tmp_path / "logs" / "rsl_rl" / "franka_lift" / "shipped"
    shutil.copytree(copy_pretrained_run("simlab/Lift-Cube-Franka-v0", "rsl_rl", str(tmp_path / "unpacked")), run)
    assert script.main(["--log_root", str(tmp_path / "logs"), "--eval_envs", "16", "--eval_seconds", "5.5"]) == 0
    out = capsys.readouterr().out
    score = float(re.search(r"criterion score \(ended within 5 cm of the goal\): ([\d.]+)", out).group(1))
    lifted = float(re.search(r"ended lifted: ([\d.]+)", out).group(1))
    assert score >= 0.8 and lifted >= score  # the goals are >= 0.25 m up: at the goal is lifted
    assert "16 episodes ran to their time limit" in out
