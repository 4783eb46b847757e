"""Cameras: the API, images of the cartpole on the CPU renderer, the camera tasks, bad input, and
the GPU renderer (MuJoCo Warp) against the CPU one on the same state."""

from __future__ import annotations

import math

import gymnasium as gym
import mujoco
import numpy as np
import pytest
import torch
from conftest import rendering_available

import simlab.sim as sim_utils
import simlab.tasks  # noqa: F401 - registers the tasks
from simlab.assets import ArticulationCfg, AssetBaseCfg
from simlab.robots.cartpole import CARTPOLE_CFG
from simlab.scene import InteractiveScene, InteractiveSceneCfg
from simlab.sensors import TiledCameraCfg
from simlab.sensors.camera.camera import camera_memory_bytes, check_gpu_memory
from simlab.sim import SimulationCfg, SimulationContext
from simlab.tasks.utils.parse_cfg import load_cfg_from_registry
from simlab.utils import configclass

# MuJoCo's OpenGL renderer draws the CPU backend's images; MuJoCo Warp's needs no GL
needs_gl = pytest.mark.skipif(not rendering_available(), reason="no offscreen OpenGL backend (libosmesa6 or EGL)")

RGB_TASK = "simlab/Cartpole-RGB-Camera-Direct-v0"
DEPTH_TASK = "simlab/Cartpole-Depth-Camera-Direct-v0"
CART_COLOUR = (0.3, 0.5, 0.7)  # the cart's rgba in simlab's cartpole MJCF


def front_camera(data_types, prim_path="{ENV_REGEX_NS}/Camera", **changes) -> TiledCameraCfg:
    """The camera of the cartpole camera tasks: 5 m in front of the rail, looking along +x."""
    cfg = TiledCameraCfg(
        prim_path=prim_path,
        offset=TiledCameraCfg.OffsetCfg(pos=(-5.0, 0.0, 2.0), rot=(1.0, 0.0, 0.0, 0.0), convention="world"),
        data_types=data_types,
        spawn=sim_utils.PinholeCameraCfg(focal_length=24.0, horizontal_aperture=20.955, clipping_range=(0.1, 20.0)),
        width=64,
        height=48,
    )
    return cfg.replace(**changes)


def cartpole_scene(camera: TiledCameraCfg, num_envs: int = 2, light: sim_utils.LightCfg | None = None):
    @configclass
    class SceneCfg(InteractiveSceneCfg):
        robot: ArticulationCfg = CARTPOLE_CFG.replace(prim_path="{ENV_REGEX_NS}/Robot")
        camera: TiledCameraCfg = None
        light: AssetBaseCfg | None = None

    sim = SimulationContext(SimulationCfg(device="cpu"))
    light = AssetBaseCfg(prim_path="/World/light", spawn=light) if light is not None else None
    scene = InteractiveScene(SceneCfg(num_envs=num_envs, env_spacing=20.0, camera=camera, light=light))
    sim.reset()
    scene.update(sim.get_physics_dt())
    return sim, scene


def set_pole(scene, angles) -> None:
    robot = scene["robot"]
    pos = robot.data.default_joint_pos.clone()
    pole, _ = robot.find_joints("cart_to_pole")
    pos[:, pole[0]] = torch.as_tensor(angles, dtype=pos.dtype)
    robot.write_joint_state_to_sim(pos, torch.zeros_like(pos))
    scene["camera"].reset()


@needs_gl
def test_camera_outputs_poses_and_intrinsics():
    kinds = ["rgb", "rgba", "depth", "distance_to_image_plane", "distance_to_camera", "semantic_segmentation"]
    sim, scene = cartpole_scene(front_camera(kinds))
    data = scene["camera"].data
    assert data.image_shape == (48, 64)
    shapes = {name: (tuple(image.shape), image.dtype) for name, image in data.output.items()}
    assert shapes == {
        "rgb": ((2, 48, 64, 3), torch.uint8),
        "rgba": ((2, 48, 64, 4), torch.uint8),
        "depth": ((2, 48, 64, 1), torch.float32),
        "distance_to_image_plane": ((2, 48, 64, 1), torch.float32),
        "distance_to_camera": ((2, 48, 64, 1), torch.float32),
        "semantic_segmentation": ((2, 48, 64, 4), torch.uint8),
    }
    depth, distance = data.output["depth"], data.output["distance_to_camera"]
    hit = torch.isfinite(depth)
    assert hit.any() and not hit.all()  # the cart in front of empty space
    # the cart's front face is 0.1 m before the rail, 5 m from the camera; rays off the axis are longer
    assert abs(depth[hit].min().item() - 4.9) < 0.02
    assert torch.all(distance[hit] >= depth[hit]) and torch.all(torch.isinf(distance[~hit]))
    assert torch.equal(data.output["rgba"][..., :3], data.output["rgb"]) and (data.output["rgba"][..., 3] == 255).all()
    # poses: each env's camera at its origin + offset, facing +x (world convention's identity)
    origins = scene.env_origins
    torch.testing.assert_close(data.pos_w, origins + torch.tensor([-5.0, 0.0, 2.0]))
    torch.testing.assert_close(data.quat_w_world, torch.tensor([[1.0, 0.0, 0.0, 0.0]] * 2), atol=1e-6, rtol=0)
    # ros: +z forward (= world +x), so its rotation maps z to x
    from simlab.utils.math import matrix_from_quat

    ros = matrix_from_quat(data.quat_w_ros)
    torch.testing.assert_close(ros[:, :, 2], torch.tensor([[1.0, 0.0, 0.0]] * 2), atol=1e-6, rtol=0)
    fx = 64 * 24.0 / 20.955
    torch.testing.assert_close(data.intrinsic_matrices[0], torch.tensor([[fx, 0, 32.0], [0, fx, 24.0], [0, 0, 1.0]]))


@needs_gl
def test_pointcloud_from_depth_lands_on_the_cart():
    """Isaac Lab's ``camera.utils.create_pointcloud_from_depth``: the pixels that hit, unprojected and placed
    by the camera's ROS pose, lie on what the camera sees (the cart's front face 0.1 m before the rail)."""
    from simlab.sensors.camera.utils import create_pointcloud_from_depth

    sim, scene = cartpole_scene(front_camera(["distance_to_image_plane"]))
    data = scene["camera"].data
    depth, k = data.output["distance_to_image_plane"][0], data.intrinsic_matrices[0]
    hit = torch.isfinite(depth)
    points = create_pointcloud_from_depth(k, depth, position=data.pos_w[0], orientation=data.quat_w_ros[0])
    assert points.shape == (int(hit.sum()), 3) and torch.isfinite(points).all()
    front = scene.env_origins[0, 0] - 0.1
    assert abs(points[:, 0].min().item() - front.item()) < 0.02 and (points[:, 0] < front + 0.3).all()
    # NumPy in, NumPy out; in the camera frame (ROS: +z forward) each point's z is its pixel's depth
    local = create_pointcloud_from_depth(k.numpy(), depth.numpy())
    assert isinstance(local, np.ndarray)
    np.testing.assert_allclose(np.sort(local[:, 2]), np.sort(depth[hit].numpy()), rtol=1e-6)
    kept = create_pointcloud_from_depth(k, depth, keep_invalid=True)
    assert kept.shape == (48 * 64, 3)


@needs_gl
def test_segmentation_ids_name_bodies():
    camera = front_camera(["semantic_segmentation"], colorize_semantic_segmentation=False, width=160, height=120)
    _, scene = cartpole_scene(camera)
    data = scene["camera"].data
    ids = data.output["semantic_segmentation"]
    assert ids.dtype == torch.int32 and ids.shape == (2, 120, 160, 1)
    # a TiledCamera's info is one dict by data type, as Isaac Lab's (a Camera's: a list, one per camera)
    assert isinstance(data.info, dict) and data.info.keys() == {"semantic_segmentation"}
    labels = data.info["semantic_segmentation"]["idToLabels"]
    seen = {labels[int(i)] for i in ids.unique() if i >= 0}
    assert {"Robot/cart", "Robot/pole"} <= seen <= {"Robot/cart", "Robot/pole", "Robot/slider"}
    assert (ids == -1).any()


def is_cart_coloured(rgb: torch.Tensor) -> torch.Tensor:
    """(..., 3) uint8 pixels of the cart's light steel blue (blue > green > red, as its rgba 0.3 0.5 0.7;
    the pole is dark blue with red = green, the rail orange): shading changes brightness, not that order."""
    r, g, b = rgb.int().unbind(-1)
    return (b > g + 10) & (g > r + 10) & (b > 80)


@needs_gl
def test_image_shows_the_cart_and_follows_the_pole():
    _, scene = cartpole_scene(front_camera(["rgb"], width=100, height=100))
    camera = scene["camera"]
    set_pole(scene, [0.0, 0.0])
    upright = camera.data.output["rgb"].clone()
    set_pole(scene, [0.0, 1.0])
    tipped = camera.data.output["rgb"].clone()
    image = upright[0].float() / 255
    assert image.std() > 0.02  # not a uniform picture
    cart = is_cart_coloured(upright[0])
    assert cart.sum() > 10  # the cart's colour is there ...
    rows, cols = cart.nonzero(as_tuple=True)
    assert abs(cols.float().mean().item() - 50) < 3 and abs(rows.float().mean().item() - 50) < 3  # ... in the middle
    torch.testing.assert_close(tipped[0], upright[0])  # env 0 did not move
    changed = (tipped[1].int() - upright[1].int()).abs().amax(dim=-1) > 30
    assert changed.sum() > 20  # env 1's pole moved


@needs_gl
def test_a_dome_light_is_the_sky_of_videos_and_not_of_camera_images():
    """A visible dome light gives the model a skybox in its colour, which a video draws above the
    horizon; a camera sensor's RGB and depth images are bit-identical with and without it (the shipped
    camera policies were trained on a black background)."""
    from simlab.sim.renderer import OffscreenRenderer

    shots = {}
    for visible in (True, False):
        dome = sim_utils.DomeLightCfg(color=(0.2, 0.4, 0.8), intensity=2000.0, visible_in_primary_ray=visible)
        sim, scene = cartpole_scene(front_camera(["rgb", "depth"]), light=dome)
        set_pole(scene, [0.0, 0.5])
        output = scene["camera"].data.output
        video = OffscreenRenderer(sim.model, 64, 48, max_envs=1)
        frame = video.render(sim.physics, [0], np.zeros((1, 3)), eye=(-5.0, 0.0, 2.0), lookat=(0.0, 0.0, 2.0))
        video.close()
        skyboxes = int((sim.model.tex_type == mujoco.mjtTexture.mjTEXTURE_SKYBOX).sum())
        shots[visible] = skyboxes, output["rgb"].clone(), output["depth"].clone(), frame
    (sky, rgb, depth, frame), (no_sky, rgb_before, depth_before, frame_before) = shots[True], shots[False]
    assert (sky, no_sky) == (1, 0)
    assert torch.isinf(depth).sum() > 100  # the camera sees past everything, where a sky would be
    assert torch.equal(rgb, rgb_before) and torch.equal(depth, depth_before)
    red, green, blue = frame[0].astype(int).T  # the video's top row: the dome's blue sky, black without it
    assert (blue > red + 40).all() and (blue > green).all()
    assert not frame_before[0].any()


@needs_gl
def test_camera_on_a_body_rides_with_it():
    cfg = front_camera(["depth"], prim_path="{ENV_REGEX_NS}/Robot/cart/cart_cam")
    cfg = cfg.replace(
        offset=TiledCameraCfg.OffsetCfg(pos=(-2.0, 0.0, 0.5), rot=(1.0, 0.0, 0.0, 0.0), convention="world")
    )
    _, scene = cartpole_scene(cfg)
    robot, camera = scene["robot"], scene["camera"]
    pos = robot.data.default_joint_pos.clone()
    cart, _ = robot.find_joints("slider_to_cart")
    pos[:, cart[0]] = torch.tensor([0.0, 1.5])
    robot.write_joint_state_to_sim(pos, torch.zeros_like(pos))
    camera.reset()
    moved = camera.data.pos_w - scene.env_origins
    torch.testing.assert_close(moved, torch.tensor([[-2.0, 0.0, 2.5], [-2.0, 1.5, 2.5]]), atol=1e-5, rtol=0)
    # the cart stays centred in both images, 2 m - 0.1 m in front
    depth = camera.data.output["depth"]
    for env in range(2):
        assert abs(depth[env][torch.isfinite(depth[env])].min().item() - 1.9) < 0.02


@needs_gl
@pytest.mark.parametrize("task", [RGB_TASK, DEPTH_TASK])
def test_camera_tasks_step_with_image_observations(task):
    cfg = load_cfg_from_registry(task, "env_cfg_entry_point")
    cfg.scene.num_envs = 2
    cfg.sim.device = "cpu"
    cfg.seed = 3
    env = gym.make(task, cfg=cfg)
    try:
        obs, _ = env.reset()
        channels = 3 if task == RGB_TASK else 1
        assert obs["policy"].shape == (2, 100, 100, channels) and obs["policy"].dtype == torch.float32
        assert env.unwrapped.single_observation_space["policy"].shape == (100, 100, channels)
        first = obs["policy"].clone()
        for _ in range(5):
            obs, reward, terminated, truncated, extras = env.step(torch.ones(2, 1))
        policy = obs["policy"]
        assert policy.shape == (2, 100, 100, channels) and torch.isfinite(policy).all()
        assert "final_obs" not in extras  # cfg.final_observations = False: one render per step
        assert not torch.equal(policy, first)  # the cart was pushed: the picture changed
        if task == RGB_TASK:  # each image minus its mean colour
            assert policy.mean(dim=(1, 2)).abs().max() < 1e-5
        else:  # metres, 0 where nothing is hit
            assert ((policy == 0) | ((policy > 4.0) & (policy < 6.0))).all() and (policy > 0).any()
        assert reward.shape == (2,)
    finally:
        env.close()


@needs_gl
def test_frame_stack_keeps_the_newest_images_and_restarts_at_a_reset():
    cfg = load_cfg_from_registry(DEPTH_TASK, "env_cfg_entry_point")
    cfg.scene.num_envs, cfg.sim.device, cfg.seed, cfg.frame_stack = 2, "cpu", 3, 2
    env = gym.make(DEPTH_TASK, cfg=cfg)
    try:
        obs, _ = env.reset()
        assert env.unwrapped.single_observation_space["policy"].shape == (100, 100, 2)
        stacked = obs["policy"]
        assert stacked.shape == (2, 100, 100, 2) and torch.equal(stacked[..., 0], stacked[..., 1])  # fresh: repeated
        previous = stacked[..., 1].clone()
        obs, *_ = env.step(torch.ones(2, 1))
        assert torch.equal(obs["policy"][..., 0], previous)  # the older image comes first
        assert not torch.equal(obs["policy"][..., 1], previous)  # the newest shows the pushed cart
        env.unwrapped._reset_idx(torch.tensor([1]))
        obs, *_ = env.step(torch.zeros(2, 1))
        assert not torch.equal(obs["policy"][0, ..., 0], obs["policy"][0, ..., 1])  # env 0 keeps its history
        assert torch.equal(obs["policy"][1, ..., 0], obs["policy"][1, ..., 1])  # env 1 starts a new one
    finally:
        env.close()
    cfg.frame_stack = 0
    with pytest.raises(ValueError, match="frame_stack must be a positive int"):
        gym.make(DEPTH_TASK, cfg=cfg)


@needs_gl
def test_save_camera_frames_writes_a_tiled_png(tmp_path):
    import imageio.v3 as iio

    from simlab.cli.main import main

    folder = tmp_path / "frames"
    code = main(["random", "--task", RGB_TASK, "--num_envs", "4", "--device", "cpu", "--headless", "--steps", "2",
                 "--enable_cameras", "--save_camera_frames", str(folder)])  # fmt: skip
    assert code == 0
    picture = iio.imread(folder / "tiled_camera_rgb_step000002.png")
    assert picture.shape == (2 * 100 + 2, 2 * 100 + 2, 3)  # 4 envs as 2 x 2 tiles, 2 px apart
    assert (folder / "tiled_camera_rgb_reset.png").is_file()
    for tile in (picture[:100, :100], picture[102:, 102:]):
        assert tile.std() > 5  # each env's tile shows something on the dark background


def test_save_camera_frames_needs_a_camera(tmp_path, capsys):
    from simlab.cli.main import main

    code = main(["random", "--task", "simlab/Cartpole-Direct-v0", "--num_envs", "2", "--device", "cpu", "--headless",
                 "--steps", "1", "--save_camera_frames", str(tmp_path)])  # fmt: skip
    assert code == 2
    assert "has no camera" in capsys.readouterr().err


# -- bad input ---------------------------------------------------------------------------------


def test_unknown_data_type_says_what_is_allowed():
    SimulationContext(SimulationCfg(device="cpu"))
    with pytest.raises(
        ValueError, match=r"unknown types \['motion_vectors'\]; allowed \(a list of any of them\).*'distance_to_camera'"
    ):
        front_camera(["rgb", "motion_vectors"]).class_type(front_camera(["rgb", "motion_vectors"]))


def test_camera_on_a_missing_body_lists_the_bodies():
    with pytest.raises(ValueError, match=r"body 'Robot/wheel'.*bodies in the model: \['Robot/slider', 'Robot/cart'"):
        cartpole_scene(front_camera(["rgb"], prim_path="{ENV_REGEX_NS}/Robot/wheel/cam"))


def test_resolution_beyond_gpu_memory_says_how_much_is_needed():
    needed = camera_memory_bytes(4096, 1920, 1080, ["rgb", "depth"], gpu=True)
    # outputs 3 + 4, unpacked 3 + 4, MuJoCo Warp's 4 + 4 bytes per pixel
    assert needed == 4096 * 1920 * 1080 * 22
    with pytest.raises(
        MemoryError, match=r"4096 envs of 1920x1080 images need about 174\.\d\d GiB.*10\.00 GiB are free"
    ):
        check_gpu_memory("Camera", needed, 10 * 1024**3, 4096, 1920, 1080)
    check_gpu_memory("Camera", camera_memory_bytes(1024, 100, 100, ["rgb"], gpu=True), 10 * 1024**3, 1024, 100, 100)


def test_bad_lens_and_resolution():
    SimulationContext(SimulationCfg(device="cpu"))
    with pytest.raises(ValueError, match="width must be a positive number of pixels"):
        front_camera(["rgb"], width=0).class_type(front_camera(["rgb"], width=0))
    bad_lens = front_camera(["rgb"], spawn=sim_utils.PinholeCameraCfg(clipping_range=(1.0, 0.5)))
    with pytest.raises(ValueError, match="0 < near < far"):
        bad_lens.class_type(bad_lens)
    blurred = front_camera(["rgb"], spawn=sim_utils.PinholeCameraCfg(f_stop=2.8))
    with pytest.raises(ValueError, match="depth of field"):
        blurred.class_type(blurred)


# -- the GPU renderer against the CPU one ------------------------------------------------------

WARP_DEVICES = [
    # MuJoCo Warp's CPU device runs wherever mujoco_warp is installed, but compiles the ray tracer for it first
    pytest.param("cpu", id="warp-cpu", marks=[pytest.mark.slow]),
    pytest.param("cuda:0", id="warp-cuda", marks=[pytest.mark.gpu]),
]


@needs_gl
@pytest.mark.parametrize("warp_device", WARP_DEVICES)
def test_warp_renderer_matches_mujoco_renderer(warp_device):
    pytest.importorskip("mujoco_warp")
    from simlab.sensors.camera.mujoco_renderer import MujocoCameraRenderer
    from simlab.sensors.camera.warp_renderer import WarpCameraRenderer
    from simlab.sim.backends.cuda import CudaBackend

    # a visible dome light: its sky is in the model, and neither renderer draws it in a camera's image
    dome = sim_utils.DomeLightCfg(color=(0.75, 0.75, 0.75), intensity=2000.0)
    sim, scene = cartpole_scene(front_camera(["rgb"]).replace(width=80, height=60), light=dome)
    set_pole(scene, [0.3, -0.8])
    physics, model, camera_id = sim.physics, sim.model, scene["camera"]._camera_id
    physics.ensure_forward()
    cpu = MujocoCameraRenderer(physics, model, camera_id, 80, 60, True, True, True)
    cpu.render()
    warp_physics = CudaBackend(model, 2, device=warp_device)
    warp_physics.data("qpos").copy_(physics.data("qpos").to(warp_physics.device))
    warp_physics.forward()
    gpu = WarpCameraRenderer(warp_physics, model, camera_id, 80, 60, True, True, True)
    gpu.render()
    depth_cpu, depth_gpu = cpu.depth.numpy(), gpu.depth.cpu().numpy()
    # the same pixels hit something, at the same planar depth
    assert np.array_equal(np.isfinite(depth_cpu), np.isfinite(depth_gpu)) and np.isfinite(depth_cpu).sum() > 50
    hit = np.isfinite(depth_cpu)
    np.testing.assert_allclose(depth_gpu[hit], depth_cpu[hit], atol=1e-3)
    assert (gpu.geom_ids.cpu() == cpu.geom_ids).float().mean() > 0.99
    # RGB: the same pixels are lit, and in the same colours (OpenGL without multisampling samples each
    # pixel's centre as the rays do; antialiased, it drew the thin rail as a line the rays miss), so a
    # policy trained on one device's images plays on the other's
    lit_cpu = cpu.rgb.int().amax(dim=-1) > 20
    lit_gpu = gpu.rgb.cpu().int().amax(dim=-1) > 20
    objects = torch.from_numpy(hit)
    assert (lit_gpu == objects).float().mean() > 0.99  # the ray tracer draws exactly the hit pixels
    assert (lit_cpu == objects).float().mean() > 0.99
    colour_gap = (cpu.rgb.int() - gpu.rgb.cpu().int()).abs()
    assert float(colour_gap.float().mean()) < 0.5 and (colour_gap.amax(dim=-1) <= 3).float().mean() > 0.99
    for rgb in (cpu.rgb, gpu.rgb.cpu()):
        assert is_cart_coloured(rgb).sum() > 10
    assert math.isclose(float(cpu.depth[torch.isfinite(cpu.depth)].min()), 4.9, abs_tol=0.02)


@needs_gl
def test_bench_env_measures_the_render_share(tmp_path):
    import json

    from simlab.benchmarks.cli import main

    out = tmp_path / "bench.json"
    args = ["env", "inference", "--device", "cpu", "--tasks", RGB_TASK, "--num_envs", "2", "--steps", "2"]
    assert main([*args, "--json", str(out)]) == 0
    results = json.loads(out.read_text())["results"]
    for row in (results["env"][0], results["inference"][0]):  # inference: the CNN actor on the images
        assert "error" not in row
        assert row["renders_per_step"] == 1  # the task computes no final observations
        assert row["render_ms"] > 0 and 0 < row["render_share"] < 1.5


@needs_gl
def test_rsl_rl_cnn_actor_trains_plays_and_exports(tmp_path):
    from simlab.cli.main import main

    common = ["--task", RGB_TASK, "--library", "rsl_rl", "--device", "cpu", "--headless", "--log_root", str(tmp_path)]
    small = ["agent.num_steps_per_env=4", "agent.algorithm.num_mini_batches=1"]
    assert main(["train", *common, "--enable_cameras", "--num_envs", "2", "--max_iterations", "1", *small]) == 0
    assert main(["play", *common, "--num_envs", "2", "--use_last_checkpoint", "--steps", "2"]) == 0
    (exported,) = list(tmp_path.glob("rsl_rl/cartpole_camera_direct/*/exported"))
    policy = torch.jit.load(str(exported / "policy.pt"))
    images = torch.rand(3, 100, 100, 3) - 0.5  # (N, H, W, C), as the env gives them
    actions = policy(images)
    assert actions.shape == (3, 1) and torch.isfinite(actions).all()
    assert (exported / "policy.onnx").is_file()


def test_camera_task_steps_on_the_mujoco_warp_backend(monkeypatch):
    """The GPU code path (MuJoCo Warp physics and renderer) through whole env steps, on MuJoCo Warp's
    CPU device: runs wherever mujoco_warp is installed."""
    pytest.importorskip("mujoco_warp")
    import simlab.sim.simulation_context as simulation_context
    from simlab.sensors.camera.warp_renderer import WarpCameraRenderer
    from simlab.sim.backends.cuda import CudaBackend

    def warp_on_cpu(model, num_envs, device, **options):
        return CudaBackend(model, num_envs, device="cpu", nconmax=options.get("nconmax"), njmax=options.get("njmax"))

    monkeypatch.setattr(simulation_context, "make_backend", warp_on_cpu)
    cfg = load_cfg_from_registry(DEPTH_TASK, "env_cfg_entry_point")
    cfg.scene.num_envs = 2
    cfg.sim.device = "cpu"
    env = gym.make(DEPTH_TASK, cfg=cfg)
    try:
        camera = env.unwrapped._tiled_camera
        assert isinstance(camera._renderer, WarpCameraRenderer)
        obs, _ = env.reset()
        for _ in range(3):
            obs, *_ = env.step(torch.ones(2, 1))
        depth = obs["policy"]
        assert depth.shape == (2, 100, 100, 1)
        hit = depth[depth > 0]
        assert hit.numel() > 50 and abs(hit.min().item() - 4.9) < 0.05
        assert int(camera.frame[0]) == 1 + 3  # the reset, then one render per step (no final observations)
    finally:
        env.close()


@pytest.mark.gpu
def test_camera_step_replays_as_a_cuda_graph_and_matches_eager_steps():
    """On the GPU the render is recorded into the env step's CUDA graph; its images equal eager steps'."""
    observations = {}
    for graphed in (True, False):
        cfg = load_cfg_from_registry(DEPTH_TASK, "env_cfg_entry_point")
        cfg.scene.num_envs = 64
        cfg.sim.device = "cuda:0"
        cfg.sim.use_cuda_graph = graphed
        cfg.seed = 11
        env = gym.make(DEPTH_TASK, cfg=cfg)
        try:
            env.reset()
            actions = torch.linspace(-1, 1, 64, device="cuda:0").unsqueeze(-1)
            for _ in range(8):
                obs, *_ = env.step(actions)
            assert env.unwrapped.step_mode == ("graphed" if graphed else "eager (cfg.sim.use_cuda_graph is False)")
            observations[graphed] = obs["policy"].cpu()
        finally:
            env.close()
    depth = observations[True]
    assert depth.shape == (64, 100, 100, 1) and (depth > 0).sum() > 64 * 50
    torch.testing.assert_close(depth, observations[False], atol=1e-3, rtol=0)


@needs_gl
def test_image_observation_term():
    from types import SimpleNamespace

    from simlab.envs import mdp
    from simlab.managers import SceneEntityCfg

    camera = front_camera(["rgb", "distance_to_camera", "distance_to_image_plane"])
    _, scene = cartpole_scene(camera)
    env = SimpleNamespace(scene=scene)
    rgb = mdp.image(env, SceneEntityCfg("camera"), "rgb")
    assert rgb.shape == (2, 48, 64, 3) and rgb.dtype == torch.float32
    assert rgb.mean(dim=(1, 2)).abs().max() < 1e-5  # each image minus its mean colour
    planar = mdp.image(env, SceneEntityCfg("camera"), "distance_to_camera", convert_perspective_to_orthogonal=True)
    expected = mdp.image(env, SceneEntityCfg("camera"), "distance_to_image_plane")
    # Isaac Lab's conversion takes rays through pixel corners, the renderers through pixel centres: ~1 mm at 5 m
    torch.testing.assert_close(planar, expected, atol=2e-3, rtol=0)
    assert (expected == 0).any() and (expected > 4.8).any()  # nothing hit: 0; the cart about 4.9 m away
