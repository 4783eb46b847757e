"""Isaac Sim's debug drawing (``isaacsim.util.debug_draw`` -> ``simlab.markers.debug_draw``): lines and
points added to every render until cleared, each in the env nearest to it."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest
import torch

from simlab.markers import debug_draw


@pytest.fixture
def draw():
    interface = debug_draw.acquire_debug_draw_interface()
    yield interface
    interface.clear_lines()
    interface.clear_points()


def _scene() -> mujoco.MjvScene:
    return mujoco.MjvScene(mujoco.MjModel.from_xml_string("<mujoco/>"), maxgeom=16)


def test_lines_and_points_become_geoms_in_their_env(draw):
    assert draw is debug_draw.acquire_debug_draw_interface()  # one drawer per process
    origins = torch.tensor([[0.0, 0.0, 0.0], [10.0, 0.0, 0.0]])
    draw.draw_lines([[0, 0, 1], [10, 0, 1]], [[1, 0, 0], [10, 0, 2]], [[1, 1, 0, 1]] * 2, [5.0, 5.0])
    draw.draw_points(torch.tensor([[10.0, 1.0, 0.0]]), [[0, 0, 1, 1]], [10])
    assert draw.get_num_lines() == 2 and draw.get_num_points() == 1
    scene = _scene()
    draw.add_to_scene(scene, 1, origins)
    assert scene.ngeom == 2  # env 1's line and point, in env 1's frame
    line, point = scene.geoms[0], scene.geoms[1]
    assert line.type == mujoco.mjtGeom.mjGEOM_LINE and line.size[0] == 5.0
    np.testing.assert_allclose(line.pos, [0, 0, 1], atol=1e-6)  # the line's start
    np.testing.assert_allclose(line.size[2], 1.0, atol=1e-6)  # its length
    np.testing.assert_allclose(line.rgba, [1, 1, 0, 1])
    assert point.type == mujoco.mjtGeom.mjGEOM_SPHERE
    np.testing.assert_allclose(point.pos, [0, 1, 0], atol=1e-6)
    np.testing.assert_allclose(point.size, [0.01] * 3)
    draw.clear_lines()
    scene = _scene()
    draw.add_to_scene(scene, 1, origins)
    assert scene.ngeom == 1 and draw.get_num_lines() == 0
    draw.clear_points()
    scene = _scene()
    draw.add_to_scene(scene, 0, origins)
    assert scene.ngeom == 0


def test_lists_of_different_lengths_are_named(draw):
    with pytest.raises(ValueError, match=r"draw_lines: the lists must be equally long .* \[1, 1, 2, 1\]"):
        draw.draw_lines([[0, 0, 0]], [[1, 0, 0]], [[1, 0, 0, 1], [1, 0, 0, 1]], [1.0])
    with pytest.raises(ValueError, match="point_list must be a list of 3-element rows"):
        draw.draw_points([[0, 0]], [[1, 0, 0, 1]], [1.0])
    assert draw.get_num_lines() == 0 and draw.get_num_points() == 0


def test_drawn_lines_and_points_show_in_a_render(draw):
    import simlab.sim as sim_utils
    from simlab.sim.renderer import OffscreenRenderer

    sim = sim_utils.SimulationContext(sim_utils.SimulationCfg(device="cpu"))
    try:
        ground = sim_utils.GroundPlaneCfg()
        ground.func("/World/ground", ground)
        sim.reset()
        try:
            renderer = OffscreenRenderer(sim.model, 160, 120, 1)
        except RuntimeError as err:  # no OpenGL on this machine
            pytest.skip(f"offscreen rendering unavailable: {err}")
        view = (sim.physics, [0], np.zeros((1, 3)), (2.0, 0.0, 1.5), (0.0, 0.0, 0.3))
        plain = renderer.render(*view).astype(np.int32)
        draw.draw_lines([[0, -0.5, 0.3]], [[0, 0.5, 0.3]], [[1, 1, 0, 1]], [5.0])
        draw.draw_points([[0, 0, 0.6]], [[0, 0, 1, 1]], [50])
        drawn = renderer.render(*view).astype(np.int32)
        renderer.close()
    finally:
        sim.clear_instance()
    changed = drawn[np.abs(drawn - plain).sum(-1) > 30]
    yellow = (changed[:, 0] > 150) & (changed[:, 1] > 150) & (changed[:, 2] < 80)
    blue = changed[:, 2] > changed[:, :2].max(-1) + 60
    assert yellow.sum() > 20 and blue.sum() > 20, (yellow.sum(), blue.sum())
