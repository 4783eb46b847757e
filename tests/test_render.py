"""Offscreen rendering: an image that follows the pole, several envs side by side, the viewer frames, the GL backend."""

from __future__ import annotations

import numpy as np
import pytest
import torch
from conftest import rendering_available

from simlab.envs import ManagerBasedRLEnv
from simlab.sim.renderer import look_at
from simlab.tasks.manager_based.classic.cartpole.cartpole_env_cfg import CartpoleEnvCfg


def test_look_at_matches_mujoco_free_camera_convention():
    lookat, distance, azimuth, elevation = look_at((8.0, 0.0, 5.0), (0.0, 0.0, 0.0))
    assert distance == pytest.approx(np.hypot(8.0, 5.0))
    assert azimuth == pytest.approx(180.0)  # looking along -x
    assert elevation == pytest.approx(-np.degrees(np.arctan2(5.0, 8.0)))  # looking down
    with pytest.raises(ValueError, match="coincide"):
        look_at((1, 2, 3), (1, 2, 3))


@pytest.fixture
def env():
    cfg = CartpoleEnvCfg()
    cfg.scene.num_envs = 2
    cfg.sim.device = "cpu"
    cfg.viewer.resolution = (160, 120)
    cfg.viewer.eye = (4.0, 0.0, 2.5)
    cfg.viewer.lookat = (0.0, 0.0, 2.0)
    cfg.viewer.origin_type = "env"
    env = ManagerBasedRLEnv(cfg, render_mode="rgb_array")
    env.reset()
    try:
        env.render()
    except RuntimeError as err:  # no OpenGL on this machine
        env.close()
        pytest.skip(f"offscreen rendering unavailable: {err}")
    yield env
    env.close()


def test_render_gives_an_image_that_follows_the_pole(env):
    robot = env.scene["robot"]
    robot.write_joint_state_to_sim(torch.zeros(2, 2), torch.zeros(2, 2))
    env.sim.forward()
    upright = env.render()
    assert upright.shape == (120, 160, 3) and upright.dtype == np.uint8
    assert upright.std() > 5  # not a blank frame
    robot.write_joint_state_to_sim(torch.tensor([[0.0, 1.2], [0.0, 1.2]]), torch.zeros(2, 2))
    env.sim.forward()
    tilted = env.render()
    changed = np.abs(upright.astype(int) - tilted.astype(int)).sum(axis=-1) > 30
    assert changed.mean() > 0.002  # the pole's pixels moved


def test_render_needs_a_render_mode():
    cfg = CartpoleEnvCfg()
    cfg.scene.num_envs = 1
    cfg.sim.device = "cpu"
    env = ManagerBasedRLEnv(cfg)
    with pytest.raises(RuntimeError, match="render_mode='rgb_array'"):
        env.render()
    env.close()


# -- several envs in one frame, the viewer's origin types, the GL backend ---------------------------


def _robot_mask(frame: np.ndarray, floor: np.ndarray) -> np.ndarray:
    """Pixels where something stands on the floor."""
    return np.abs(frame.astype(int) - floor.astype(int)).sum(axis=-1) > 40


def _blobs(mask: np.ndarray, min_pixels: int = 4) -> int:
    """Connected groups of True pixels (4-neighbour flood fill) with at least ``min_pixels``."""
    seen = np.zeros_like(mask)
    count = 0
    for start in zip(*np.nonzero(mask)):
        if seen[start]:
            continue
        stack, size = [start], 0
        seen[start] = True
        while stack:
            r, c = stack.pop()
            size += 1
            for nr, nc in ((r + 1, c), (r - 1, c), (r, c + 1), (r, c - 1)):
                if 0 <= nr < mask.shape[0] and 0 <= nc < mask.shape[1] and mask[nr, nc] and not seen[nr, nc]:
                    seen[nr, nc] = True
                    stack.append((nr, nc))
        count += size >= min_pixels
    return count


def _floor_only(env, frame_envs, renderer_cls, resolution):
    """The same view with every geom but the ground invisible: the empty scene."""
    import copy

    import mujoco

    model = copy.deepcopy(env.sim.model)
    model.geom_rgba[model.geom_type != mujoco.mjtGeom.mjGEOM_PLANE, 3] = 0.0
    renderer = renderer_cls(model, *resolution)
    try:
        return renderer.render(
            env.sim.physics, frame_envs.env_ids, frame_envs.offsets, frame_envs.eye, frame_envs.lookat
        )
    finally:
        renderer.close()


@pytest.fixture
def ants():
    import gymnasium as gym

    import simlab.tasks  # noqa: F401 - registers the tasks
    from simlab.tasks.utils import load_cfg_from_registry

    if not rendering_available():
        pytest.skip("no offscreen OpenGL backend (install libosmesa6 or an EGL driver)")
    cfg = load_cfg_from_registry("simlab/Ant-Direct-v0", "env_cfg_entry_point")
    cfg.scene.num_envs = 16
    cfg.sim.device = "cpu"
    cfg.seed = 0
    cfg.viewer.resolution = (160, 120)
    env = gym.make("simlab/Ant-Direct-v0", cfg=cfg, render_mode="rgb_array")
    env.reset()
    yield env.unwrapped
    env.close()


def test_frame_shows_the_robots_of_several_envs(ants):
    from simlab.envs.utils.viewer import view_frame
    from simlab.sim.renderer import OffscreenRenderer

    frame = ants.render()
    shown = view_frame(ants, ants.cfg.viewer)
    assert len(shown.env_ids) == 16 and shown.env_ids[0] == ants.cfg.viewer.env_index
    floor = _floor_only(ants, shown, OffscreenRenderer, ants.cfg.viewer.resolution)
    robots = _robot_mask(frame, floor)
    assert robots.mean() > 0.02, "the frame shows only the floor"
    assert _blobs(robots) >= 6, "fewer than six robots are visible side by side"


def test_origin_types_place_the_camera_as_isaac_lab_does(ants):
    from simlab.envs.utils.viewer import camera_pose, view_frame

    viewer = ants.cfg.viewer
    origins = ants.scene.env_origins.numpy().astype(np.float64)
    viewer.env_index, viewer.eye, viewer.lookat = 5, (3.0, 0.0, 2.0), (0.0, 0.0, 0.0)
    viewer.origin_type = "world"  # world-frame points, seen from env 5's MuJoCo frame
    eye, lookat = camera_pose(ants, viewer)
    np.testing.assert_allclose(eye, np.array([3.0, 0.0, 2.0]) - origins[5])
    np.testing.assert_allclose(lookat, -origins[5])
    viewer.origin_type = "env"  # relative to env 5's origin
    eye, lookat = camera_pose(ants, viewer)
    np.testing.assert_allclose(eye, [3.0, 0.0, 2.0])
    np.testing.assert_allclose(lookat, [0.0, 0.0, 0.0])
    viewer.origin_type, viewer.asset_name = "asset_root", "robot"  # follows the ant's torso
    root = ants.scene["robot"].data.root_pos_w[5].numpy().astype(np.float64)
    eye, lookat = camera_pose(ants, viewer)
    np.testing.assert_allclose(lookat, root - origins[5], atol=1e-6)
    np.testing.assert_allclose(eye - lookat, [3.0, 0.0, 2.0], atol=1e-6)
    shown = view_frame(ants, viewer, max_envs=4)
    assert shown.env_ids[0] == 5 and len(shown.env_ids) == 4
    np.testing.assert_allclose(shown.offsets, origins[shown.env_ids] - origins[5])
    # the followed ant is in the middle of the image
    frame = ants.render()
    h, w = frame.shape[:2]
    centre = frame[h // 2 - 5 : h // 2 + 5, w // 2 - 5 : w // 2 + 5].astype(int)
    assert np.abs(centre - np.array([210, 90, 30])).sum(axis=-1).min() < 120  # the ant's orange
    viewer.origin_type = "asset_rot"
    with pytest.raises(ValueError, match="allowed: world, env, asset_root, asset_body"):
        camera_pose(ants, viewer)


def test_a_world_camera_frames_the_shown_robots_and_lights_them():
    """Cartpole's camera looks at the world origin on the ground from (8, 0, 5): the video's frames
    turn it to the middle of the shown cartpoles (2 m up on their rails), and light them."""
    from simlab.envs.utils.viewer import camera_pose, view_frame
    from simlab.sim.renderer import OffscreenRenderer

    if not rendering_available():
        pytest.skip("no offscreen OpenGL backend (install libosmesa6 or an EGL driver)")
    cfg = CartpoleEnvCfg()
    cfg.scene.num_envs = 64  # env 0, the reference, lies in a corner 20 m from the origin looked at
    cfg.sim.device = "cpu"
    cfg.viewer.resolution = (320, 240)
    env = ManagerBasedRLEnv(cfg, render_mode="rgb_array")
    try:
        env.reset()
        frame = env.render()
        shown = view_frame(env, env.cfg.viewer)
        floor = _floor_only(env, shown, OffscreenRenderer, cfg.viewer.resolution)
        configured_eye, configured_lookat = camera_pose(env, env.cfg.viewer)
    finally:
        env.close()
    # the camera keeps its direction and distance, aimed at the rails' height
    np.testing.assert_allclose(shown.eye - shown.lookat, configured_eye - configured_lookat, atol=1e-6)
    assert 1.5 < shown.lookat[2] < 2.8
    robots = _robot_mask(frame, floor)
    rows = np.nonzero(robots)[0]
    assert robots.mean() > 0.01
    assert 0.3 < rows.mean() / frame.shape[0] < 0.7, "the robots are not in the middle of the frame"
    assert robots[frame.shape[0] // 2 :].mean() > 0.005, "the lower half is empty floor"
    luminance = frame.astype(float) @ [0.299, 0.587, 0.114]
    assert luminance.mean() > 45, f"a dark frame (mean luminance {luminance.mean():.0f} of 255)"


def test_gl_backend_is_chosen_and_explained(monkeypatch):
    from simlab.utils import gl_backend

    monkeypatch.delenv("MUJOCO_GL", raising=False)
    monkeypatch.setattr(gl_backend, "_checked", {})
    if rendering_available():
        assert gl_backend.choose_gl_backend() in gl_backend.OFFSCREEN_BACKENDS
    monkeypatch.delenv("MUJOCO_GL", raising=False)
    monkeypatch.setattr(gl_backend, "_checked", {"egl": "no EGL device", "osmesa": "libOSMesa.so: not found"})
    with pytest.raises(gl_backend.GLBackendError, match="libosmesa6") as err:
        gl_backend.choose_gl_backend()
    assert "no EGL device" in str(err.value) and "libegl1" in str(err.value)
    monkeypatch.setenv("MUJOCO_GL", "bogus")
    monkeypatch.setattr(gl_backend, "_checked", {})
    with pytest.raises(gl_backend.GLBackendError, match="MUJOCO_GL=bogus fails"):
        gl_backend.check_gl_backend()


@pytest.mark.skipif(not rendering_available(), reason="offscreen rendering unavailable")
def test_a_large_scene_does_not_clip_what_is_near_the_camera():
    # A 200 m ground (a generated terrain's size) puts MuJoCo's near plane, a share of the model's
    # extent, metres from the camera; the viewer's frames must still show a red box 0.3 m in front of
    # it, and the model keeps its own setting (camera sensors use it).
    import mujoco

    from simlab.sim.renderer import NEAR_CLIP_M, near_clip_limited, open_mujoco_renderer, set_free_camera

    spec = mujoco.MjSpec()
    spec.worldbody.add_geom(type=mujoco.mjtGeom.mjGEOM_BOX, size=[100, 100, 0.1], pos=[0, 0, -0.1], rgba=[0.5] * 4)
    spec.worldbody.add_geom(type=mujoco.mjtGeom.mjGEOM_BOX, size=[0.05] * 3, pos=[0.3, 0, 1], rgba=[1, 0, 0, 1])
    model = spec.compile()
    assert model.stat.extent > 50
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    renderer = open_mujoco_renderer(model, 64, 48)
    camera = mujoco.MjvCamera()
    set_free_camera(camera, (0.0, 0.0, 1.0), (1.0, 0.0, 1.0))

    def red_centre() -> float:
        image = renderer.render()
        red = (image[..., 0] > 150) & (image[..., 1] < 80) & (image[..., 2] < 80)
        return float(red[18:30, 26:38].mean())

    try:
        renderer.update_scene(data, camera)
        assert red_centre() < 0.1  # MuJoCo's own near plane cuts the box away
        znear = model.vis.map.znear
        with near_clip_limited(model):
            assert model.vis.map.znear * model.stat.extent <= NEAR_CLIP_M + 1e-9
            renderer.update_scene(data, camera)
        assert model.vis.map.znear == znear
        assert red_centre() > 0.9  # the box fills the image's centre
    finally:
        renderer.close()


def test_a_velocity_tasks_video_follows_its_robot_over_generated_terrain():
    """On rough terrain each env starts on its own tile, away from the world origin: the velocity
    tasks' camera follows the robot, so a one-env video shows it (it showed only the floor)."""
    if not rendering_available():
        pytest.skip("offscreen rendering unavailable")
    from simlab.tasks.utils.parse_cfg import parse_env_cfg

    cfg = parse_env_cfg("simlab/Velocity-Rough-Anymal-C-v0", device="cpu", num_envs=1)
    cfg.viewer.resolution = (160, 120)
    env = ManagerBasedRLEnv(cfg, render_mode="rgb_array")
    try:
        env.reset()
        frame = env.render().astype(int)
    finally:
        env.close()
    red, green, blue = frame[..., 0], frame[..., 1], frame[..., 2]
    robot = (red > green + 50) & (red > blue + 50)  # ANYmal's orange shell against grey terrain
    assert robot.mean() > 0.01, f"{robot.mean():.4f} of the frame shows the robot"


def test_neighbour_envs_do_not_draw_the_ground_again(monkeypatch):
    """Every env's world holds the ground: a neighbour's copy, moved by its env offset, lay in the
    reference's plane and z-fought with it (jagged dark patches across the G1/H1/hand videos). Only the
    ground is hidden: a finite plane on the world body (a wall) is each env's own and stays drawn."""
    import mujoco

    from simlab.sim.renderer import EnvSceneBuilder
    from simlab.sim.spawners.from_files import GroundPlaneCfg, from_files

    spec = mujoco.MjSpec.from_string("""<mujoco><worldbody>
      <geom name="wall" type="plane" size="1 1 0.1" pos="0 1 1" zaxis="0 -1 0" rgba="0.5 0.5 0.5 1"/>
      <body name="box" pos="0 0 0.5"><freejoint/><geom type="box" size="0.1 0.1 0.1"/></body>
    </worldbody></mujoco>""")
    monkeypatch.setattr(from_files, "current_spec", lambda: spec)
    from_files.spawn_ground_plane("/World/ground", GroundPlaneCfg())  # as the terrain makes it: 100 x 100 m
    model = spec.compile()
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    states = {"qpos": np.stack([data.qpos, data.qpos]), "qvel": np.stack([data.qvel, data.qvel])}
    scene = mujoco.MjvScene(model, maxgeom=100)
    camera = mujoco.MjvCamera()
    EnvSceneBuilder(model).build(scene, states, np.array([[0.0, 0.0, 0.0], [2.5, 0.0, 0.0]]), camera)
    shown = [g for g in scene.geoms[: scene.ngeom] if g.rgba[3] > 0]
    planes = [g for g in shown if g.type == mujoco.mjtGeom.mjGEOM_PLANE]
    boxes = [g for g in shown if g.type == mujoco.mjtGeom.mjGEOM_BOX]
    ground, wall = (mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, n) for n in ("ground", "wall"))
    assert sorted(g.objid for g in planes) == sorted([ground, wall, wall])  # one ground, both envs' walls
    assert len(boxes) == 2  # both envs' boxes
