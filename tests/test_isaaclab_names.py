"""Names Isaac Lab's tutorials and task files import that simlab maps: the renderer settings
(``sim_utils.RenderCfg``), ``simlab.assets.articulation.ArticulationCfg``, ``simlab.controllers.utils``,
``AppLauncher(experience=...)``."""

from __future__ import annotations

import warnings

import mujoco
import pytest

import simlab.sim as sim_utils
from simlab.utils.errors import ConfigError


def _compiled(render: sim_utils.RenderCfg) -> mujoco.MjModel:
    sim = sim_utils.SimulationContext(sim_utils.SimulationCfg(device="cpu", render=render))
    sim.spec.worldbody.add_light(pos=[0, 0, 3], castshadow=True)
    sim.spec.worldbody.add_geom(type=mujoco.mjtGeom.mjGEOM_PLANE, size=[1, 1, 0.1])
    sim.reset()
    return sim.model


def test_render_cfg_maps_antialiasing_and_shadows_and_notes_the_rest_once():
    default = _compiled(sim_utils.RenderCfg())
    assert default.vis.quality.offsamples == 4 and default.light_castshadow.all()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        model = _compiled(
            sim_utils.RenderCfg(antialiasing_mode="Off", enable_shadows=False, enable_reflections=True, dlss_mode=2)
        )
        _compiled(sim_utils.RenderCfg(enable_reflections=True, dlss_mode=2))
    assert model.vis.quality.offsamples == 0 and not model.light_castshadow.any()
    notes = [str(w.message) for w in caught if "SimulationCfg.render" in str(w.message)]
    assert len(notes) == 1 and "enable_reflections, dlss_mode" in notes[0] and "\n" not in notes[0]


def test_articulation_cfg_from_the_articulation_module():
    from simlab.assets import ArticulationCfg as from_package
    from simlab.assets.articulation import ArticulationCfg

    assert ArticulationCfg is from_package


def test_controllers_utils_edit_urdf_joints(tmp_path):
    from simlab.controllers.utils import (
        change_revolute_to_fixed,
        change_revolute_to_fixed_regex,
        convert_usd_to_urdf,
        resolve_rmpflow_path,
    )

    urdf = tmp_path / "r.urdf"
    joints = "".join(f'<joint name="{n}" type="revolute"></joint>' for n in ("hip", "knee_l", "knee_r"))
    urdf.write_text(f"<robot>{joints}</robot>")
    change_revolute_to_fixed(str(urdf), ["hip"])
    assert '<joint name="hip" type="fixed">' in urdf.read_text()
    change_revolute_to_fixed_regex(str(urdf), ["knee_.*"])
    assert urdf.read_text().count('type="fixed"') == 3
    assert resolve_rmpflow_path("/a/b.yaml") == "/a/b.yaml"
    with pytest.raises(ConfigError, match="RMPflow"):
        resolve_rmpflow_path("rmpflow_ext:configs/franka.yaml")
    with pytest.raises(ConfigError, match="reads no USD"):
        convert_usd_to_urdf("robot.usd", str(tmp_path))


def test_app_launcher_accepts_kit_settings(capsys):
    import argparse

    from simlab.app import AppLauncher

    parser = argparse.ArgumentParser()
    AppLauncher.add_app_launcher_args(parser)
    args = parser.parse_args(["--headless", "--experience", "isaaclab.python.headless.rendering.kit"])
    launcher = AppLauncher(args)
    assert launcher.headless
    AppLauncher(headless=True, experience="my.kit", rendering_mode="quality")
    out = capsys.readouterr().out
    assert "experience='my.kit'" in out and "rendering_mode='quality'" in out and "ignored" in out
