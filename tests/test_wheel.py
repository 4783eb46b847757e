"""The wheel: ``python -m build`` makes a wheel and an sdist holding every model, motion clip and
shipped policy; installed into a clean venv (torch pinned by constraints.txt), the README's train
command and ``simlab play --use_pretrained_checkpoint`` run from it in a folder that is not the
checkout. Slow (minutes: the install), and it runs with the slow set: nothing here is skipped."""

from __future__ import annotations

import os
import subprocess
import sys
import tarfile
import zipfile
from pathlib import Path

import pytest

pytestmark = pytest.mark.slow

REPO = Path(__file__).resolve().parents[1]
# the package's data: robot and scene models, motion clips, shipped policies and their metadata
DATA = (".xml", ".urdf", ".stl", ".obj", ".npz", ".pt", ".yaml", ".json", ".txt")


def _package_data() -> list[str]:
    """The package's data files in the repository (git's list: what a clean checkout holds)."""
    listed = subprocess.run(["git", "ls-files", "simlab"], cwd=REPO, capture_output=True, text=True, check=True)
    return sorted(f for f in listed.stdout.split() if f.endswith(DATA))


def _run(command: list, cwd: Path, timeout: float = 900) -> str:
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "VIRTUAL_ENV")}
    done = subprocess.run([str(c) for c in command], cwd=cwd, env=env, capture_output=True, text=True, timeout=timeout)
    assert done.returncode == 0, f"{command} exited with {done.returncode}:\n{done.stdout[-3000:]}{done.stderr[-3000:]}"
    return done.stdout


def test_the_wheel_holds_the_data_and_trains_and_plays_from_a_clean_venv(tmp_path):
    dist = tmp_path / "dist"
    _run([sys.executable, "-m", "build", "--outdir", dist, REPO], cwd=tmp_path)
    (wheel,) = dist.glob("simlab-*.whl")
    (sdist,) = dist.glob("simlab-*.tar.gz")

    data = _package_data()
    for kind in (".xml", ".npz", "/policy.pt"):  # models (meshes too, when there are), clips, policies
        assert any(f.endswith(kind) for f in data), kind
    in_wheel = set(zipfile.ZipFile(wheel).namelist())
    assert [f for f in data if f not in in_wheel] == []
    with tarfile.open(sdist) as tar:
        in_sdist = {name.split("/", 1)[1] for name in tar.getnames() if "/" in name}
    assert [f for f in data if f not in in_sdist] == []

    venv = tmp_path / "venv"
    _run([sys.executable, "-m", "venv", venv], cwd=tmp_path)  # no system site-packages
    python = venv / "bin" / "python"
    constraints = ["-c", REPO / "constraints.txt"]
    _run([python, "-m", "pip", "install", "-q", "--upgrade", "pip"], cwd=tmp_path)  # PEP 685: rsl_rl = rsl-rl
    _run([python, "-m", "pip", "install", "-q", *constraints, "torch==2.13.0"], cwd=tmp_path, timeout=1800)
    _run([python, "-m", "pip", "install", "-q", *constraints, f"{wheel}[train,rsl_rl]"], cwd=tmp_path, timeout=1800)

    work = tmp_path / "work"  # not the checkout: simlab comes from the venv
    work.mkdir()
    installed = Path(_run([python, "-c", "import simlab; print(simlab.__file__)"], cwd=work).strip()).parent
    assert installed.is_relative_to(venv)
    shipped = installed / "pretrained" / "Cartpole-v0" / "rsl_rl"
    files_before = sorted(p.relative_to(shipped) for p in shipped.rglob("*"))

    simlab = venv / "bin" / "simlab"
    _run([simlab, "train", "--task", "simlab/Cartpole-v0", "--headless", "--max_iterations", "2"], cwd=work)
    assert list(work.glob("logs/rsl_rl/cartpole/*/model_1.pt"))
    play = [simlab, "play", "--task", "simlab/Cartpole-v0", "--use_pretrained_checkpoint", "--headless"]
    _run([*play, "--steps", "50"], cwd=work)
    exported = work / "logs" / "pretrained" / "rsl_rl" / "Cartpole-v0" / "exported"
    assert (exported / "policy.onnx").is_file() and (exported / "policy.pt").is_file()
    assert sorted(p.relative_to(shipped) for p in shipped.rglob("*")) == files_before  # the package is untouched
