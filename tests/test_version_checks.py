"""Patches of other libraries and calls into their private code run only with the release they were
checked with (simlab.utils.versions); with another installed, each takes the library's own path."""

from __future__ import annotations

import importlib.metadata
import os

import pytest
import torch

from simlab.utils import versions
from simlab.utils.io import atomic_torch_saves


@pytest.fixture
def other_release(monkeypatch):
    """Pretend ``name`` is installed at another release than the checked one."""
    installed = importlib.metadata.version

    def pretend(name: str) -> None:
        monkeypatch.setattr(importlib.metadata, "version", lambda dist: "99.0.0" if dist == name else installed(dist))
        monkeypatch.setattr(versions, "_warned", set())

    return pretend


def test_the_checked_releases_are_the_installed_ones():
    """constraints.txt installs them: CI runs the patched paths."""
    for distribution in versions.CHECKED_RELEASES:
        try:
            importlib.metadata.version(distribution)
        except importlib.metadata.PackageNotFoundError:
            continue  # an optional extra not installed here (mujoco-warp, rsl-rl-lib)
        assert versions.release_mismatch(distribution) is None, distribution


def test_release_mismatch_matches_leading_parts_and_names_what_is_installed(other_release):
    assert versions.release_mismatch("torch", "2") is None  # 2.13.0+cpu is a 2 release
    other_release("torch")
    assert versions.release_mismatch("torch") == "torch 99.0.0 is installed, not 2.13"
    assert versions.release_mismatch("no-such-distribution-here", "1.0") == "no-such-distribution-here is not installed"


def test_atomic_saves_patch_torch_save_only_with_the_checked_torch(tmp_path, other_release):
    plain = torch.save
    with atomic_torch_saves():
        assert torch.save is not plain
        torch.save({"a": 1}, tmp_path / "a.pt")
    assert torch.save is plain and torch.load(tmp_path / "a.pt") == {"a": 1}
    other_release("torch")
    with (
        pytest.warns(
            UserWarning, match="torch 99.0.0 is installed, not 2.13: checkpoints are written with torch's own"
        ),
        atomic_torch_saves(),
    ):
        assert torch.save is plain  # no process-wide patch
        torch.save({"b": 2}, tmp_path / "b.pt")
    assert torch.load(tmp_path / "b.pt") == {"b": 2} and not [f for f in os.listdir(tmp_path) if f.startswith(".")]


def test_capturable_distributions_refuse_another_torch(other_release):
    from torch.distributions import Normal

    from simlab.rl.rsl_rl.capturable import capturable_distributions, capturable_distributions_unsupported

    assert capturable_distributions_unsupported() is None
    other_release("torch")
    assert capturable_distributions_unsupported().startswith("torch 99.0.0 is installed, not 2.13")
    plain = Normal.sample
    with pytest.raises(RuntimeError, match="torch 99.0.0"), capturable_distributions():
        pass
    assert Normal.sample is plain


def test_mujocos_gl_context_is_left_alone_with_another_mujoco(other_release):
    from mujoco.rendering.classic import gl_context

    from simlab.sim.renderer import _install_gl_context

    chosen = gl_context.GLContext
    other_release("mujoco")
    with pytest.warns(UserWarning, match="mujoco 99.0.0 is installed, not 3.14"):
        _install_gl_context("egl" if "osmesa" in chosen.__module__ else "osmesa")
    assert gl_context.GLContext is chosen


def test_mujoco_warps_private_row_estimate_is_used_only_with_the_checked_release(other_release):
    mjw = pytest.importorskip("mujoco_warp")
    import mujoco

    from simlab.sim.backends.cuda import _contact_rows_estimate

    model = mujoco.MjModel.from_xml_string(
        "<mujoco><worldbody><geom type='plane' size='1 1 .1'/><body><freejoint/><geom size='.1'/></body>"
        "</worldbody></mujoco>"
    )
    data = mujoco.MjData(model)
    assert _contact_rows_estimate(mjw, model, data, 3) > 3
    other_release("mujoco-warp")
    with pytest.warns(UserWarning, match="njmax is left to MuJoCo Warp's default"):
        assert _contact_rows_estimate(mjw, model, data, 3) is None


@pytest.mark.slow  # compiles MuJoCo Warp's ray kernels for Warp's CPU device (about 10 s, then cached)
def test_the_warp_ray_caster_runs_without_mujoco_warps_private_types():
    pytest.importorskip("mujoco_warp")
    from types import SimpleNamespace

    import mujoco

    from simlab.sensors.ray_caster.ray_targets import _WarpCaster

    model = mujoco.MjModel.from_xml_string(
        "<mujoco><worldbody><geom type='plane' size='5 5 .1'/><geom type='box' pos='1 0 .5' size='.2 .2 .5'/>"
        "</worldbody></mujoco>"
    )
    caster = _WarpCaster(model, 2, SimpleNamespace(run_warp=lambda key, launch: launch()), "cpu")
    down = torch.tensor([[0.0, 0.0, -1.0], [0.0, 0.0, -1.0]])
    distances = caster.cast(torch.tensor([[0.0, 0.0, 2.0], [1.0, 0.0, 2.0]]), down)
    torch.testing.assert_close(distances, torch.tensor([2.0, 1.0]))  # the ground; the box's top
