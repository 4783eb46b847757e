"""Compiling MuJoCo Warp's kernels ahead, on a thread pool (simlab.sim.backends.warp_compile).

Run on Warp's CPU device: the look-ahead finds every module step, forward and reset load, its dry
passes write nothing, and the physics is bit-identical with it turned off. The first run compiles
the CPU kernels (tens of seconds on two cores); Warp's kernel cache serves later runs.
"""

from __future__ import annotations

import os
import subprocess
import sys

import mujoco
import pytest
import torch

pytest.importorskip("mujoco_warp")

from simlab.sim.backends import warp_compile  # noqa: E402
from simlab.sim.backends.cuda import CudaBackend  # noqa: E402
from simlab.utils.errors import ConfigError  # noqa: E402

XML = """<mujoco><worldbody><geom type="plane" size="5 5 .1"/>
<body pos="0 0 .3"><freejoint/><geom type="box" size=".1 .1 .1"/></body>
<body pos="0.3 0 .3"><freejoint/><geom type="capsule" size=".05 .1"/></body>
<body pos="-0.3 0 .3"><freejoint/><geom type="sphere" size=".1"/></body></worldbody></mujoco>"""


@pytest.fixture(scope="module")
def model() -> mujoco.MjModel:
    return mujoco.MjModel.from_xml_string(XML)


def _state(backend: CudaBackend) -> dict[str, torch.Tensor]:
    return {name: backend.data(name).clone() for name in ("qpos", "qvel", "qacc", "xpos", "qfrc_constraint", "time")}


LOOK_AHEAD = """
import os, sys, mujoco, warp as wp
sys.path.insert(0, os.environ["TESTS_DIR"])
from test_warp_compile import XML
from simlab.sim.backends import warp_compile
from simlab.sim.backends.cuda import CudaBackend

os.environ["SIMLAB_COMPILE_AHEAD"] = "0"
backend = CudaBackend(mujoco.MjModel.from_xml_string(XML), 3, device="cpu")
calls = backend._physics_calls()
missing = []  # a fresh process has loaded none of MuJoCo Warp's modules (the disk cache may hold them)
for call in calls:
    assert warp_compile._dry_run(wp, backend.wp_device, call, missing)
precompile = warp_compile.compile_ahead(wp, backend.wp_device, calls, workers=2)
assert precompile.modules == len({(id(m), b) for m, b in missing}) > 10, precompile.modules
precompile.wait()
for call in calls:  # a dry pass now notes nothing: all were compiled ahead
    noted = []
    assert warp_compile._dry_run(wp, backend.wp_device, call, noted)
    assert noted == [], [m.name for m, _ in noted]
print("modules", precompile.modules)
"""


def test_the_look_ahead_finds_every_module_the_physics_loads():
    """In a fresh process (this one may have loaded them already): the dry passes find the modules
    step, forward and reset load, and once they are compiled ahead none is left to load."""
    env = dict(os.environ, TESTS_DIR=os.path.dirname(os.path.abspath(__file__)))
    done = subprocess.run([sys.executable, "-c", LOOK_AHEAD], env=env, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stdout[-2000:] + done.stderr[-3000:]
    assert int(done.stdout.split("modules")[-1]) > 10


def test_dry_passes_write_nothing_and_the_physics_is_unchanged(model, monkeypatch):
    import warp as wp

    ahead = CudaBackend(model, 3, device="cpu")
    monkeypatch.setenv("SIMLAB_COMPILE_AHEAD", "0")
    plain = CudaBackend(model, 3, device="cpu")
    assert plain.precompile is None
    for backend in (ahead, plain):
        for _ in range(150):
            backend.step()
    before = _state(ahead)
    assert before["qfrc_constraint"].abs().sum() > 0  # the bodies landed: contacts push back
    # look ahead again in a stepped state: the dry passes launch nothing and write nothing
    noted: list = []
    for call in ahead._physics_calls():
        warp_compile._dry_run(wp, ahead.wp_device, call, noted)
    after = _state(ahead)
    for name, value in before.items():
        assert torch.equal(value, after[name]), name
        assert torch.equal(value, _state(plain)[name]), name  # same physics with and without


def test_another_warp_release_compiles_at_first_launch(model, monkeypatch):
    from simlab.utils import versions

    monkeypatch.setattr(versions, "_warned", set())
    monkeypatch.setattr(warp_compile, "release_mismatch", lambda dist: f"{dist} 99.0 is installed, not 1.19")
    with pytest.warns(UserWarning, match="compile one by one at their first launch"):
        assert not warp_compile.compile_ahead_enabled()
    monkeypatch.setattr(warp_compile, "release_mismatch", lambda dist: None)
    monkeypatch.setenv("SIMLAB_COMPILE_AHEAD", "0")
    assert not warp_compile.compile_ahead_enabled()
    monkeypatch.setenv("SIMLAB_COMPILE_AHEAD", "1")
    assert warp_compile.compile_ahead_enabled()
    monkeypatch.setenv("SIMLAB_COMPILE_AHEAD", "off")
    with pytest.raises(ConfigError, match=r"SIMLAB_COMPILE_AHEAD='off': use 1 .* or 0"):
        warp_compile.compile_ahead_enabled()


def test_a_pass_that_stops_at_a_query_goes_further_in_the_next(monkeypatch):
    """A query that needs a loaded module ends the pass; the next pass finds what lies beyond."""
    import warp as wp

    @wp.kernel
    def first(x: wp.array(dtype=float)):
        x[wp.tid()] = 1.0

    @wp.kernel(module="unique")
    def second(x: wp.array(dtype=float)):
        x[wp.tid()] += 1.0

    x = wp.zeros(4, dtype=float, device="cpu")

    def call() -> None:
        wp.launch(first, dim=4, inputs=[x])
        if second.module.load(wp.get_device("cpu"), 1) is None:  # as get_suggested_block_size raises
            raise RuntimeError("Failed to load module")
        wp.launch(second, dim=4, inputs=[x])

    pre = warp_compile.compile_ahead(wp, wp.get_device("cpu"), [call], workers=2)
    pre.wait()
    assert pre.passes == 2 and pre.modules == 2
    assert x.numpy().tolist() == [0.0] * 4  # nothing ran
    call()
    assert x.numpy().tolist() == [2.0] * 4
