"""The ray-cast camera against images computed here: a camera over a flat ground (depth equal to its
height, distance growing as height / cos toward the corners, normals up), one looking level (rows
below the horizon at h * fy / (v - cy), misses clipped as asked), one riding a body; and the
Replicator-style writer's files."""

from __future__ import annotations

import math

import numpy as np
import pytest
import torch
from conftest import DEVICES

import simlab.sim as sim_utils
from simlab.assets import AssetBaseCfg, RigidObject, RigidObjectCfg
from simlab.scene import InteractiveScene, InteractiveSceneCfg
from simlab.sensors import patterns
from simlab.sensors.ray_caster import RayCasterCamera, RayCasterCameraCfg
from simlab.sensors.replicator import BasicWriter
from simlab.sim.utils import create_prim
from simlab.utils import configclass

LENS = {"focal_length": 24.0, "horizontal_aperture": 20.955, "width": 8, "height": 6}


def make_sim(device: str = "cpu") -> sim_utils.SimulationContext:
    sim = sim_utils.SimulationContext(sim_utils.SimulationCfg(device=device))
    ground = sim_utils.GroundPlaneCfg()
    ground.func("/World/ground", ground)
    return sim


def camera_cfg(**kw) -> RayCasterCameraCfg:
    kw.setdefault("pattern_cfg", patterns.PinholeCameraPatternCfg(**LENS))
    return RayCasterCameraCfg(prim_path="/World/Origin_.*/CameraSensor", mesh_prim_paths=["/World/ground"], **kw)


def pixel_tangents(k: torch.Tensor, height: int, width: int) -> tuple[torch.Tensor, torch.Tensor]:
    """(H, W) x and y of each pixel centre's ray per unit of depth (right and down)."""
    v, u = torch.meshgrid(torch.arange(height) + 0.5, torch.arange(width) + 0.5, indexing="ij")
    return (u - k[0, 2]) / k[0, 0], (v - k[1, 2]) / k[1, 1]


@pytest.mark.parametrize("device", DEVICES)
def test_looking_down_at_flat_ground(device):
    """Two groups (two worlds); the lens's principal point moved right so that left and right differ."""
    sim = make_sim(device)
    create_prim("/World/Origin_00/CameraSensor", "Xform")
    create_prim("/World/Origin_01/CameraSensor", "Xform", translation=(5.0, 0.0, 0.0))
    lens = patterns.PinholeCameraPatternCfg(**LENS, horizontal_aperture_offset=0.1)
    camera = RayCasterCamera(
        camera_cfg(data_types=["distance_to_image_plane", "normals", "distance_to_camera"], pattern_cfg=lens)
    )
    sim.reset()
    assert sim.num_envs == 2 and camera.num_instances == 2
    heights = torch.tensor([2.0, 3.0])
    eyes = torch.tensor([[0.0, 0.0, 2.0], [5.0, 0.0, 3.0]])
    camera.set_world_poses_from_view(eyes, eyes * torch.tensor([1.0, 1.0, 0.0]))
    sim.step()
    camera.update(sim.get_physics_dt())
    data = camera.data
    fx = 8 * 24.0 / 20.955
    fy = 6 * 24.0 / (20.955 * 6 / 8)  # square pixels: the vertical aperture from the aspect ratio
    k = torch.tensor([[fx, 0.0, 0.1 * fx + 4.0], [0.0, fy, 3.0], [0.0, 0.0, 1.0]])
    torch.testing.assert_close(data.intrinsic_matrices.cpu(), k.expand(2, 3, 3))
    torch.testing.assert_close(data.pos_w.cpu(), eyes)
    x, y = pixel_tangents(k, 6, 8)
    plane = data.output["distance_to_image_plane"].cpu()
    assert plane.shape == (2, 6, 8, 1)
    torch.testing.assert_close(plane[..., 0], heights.view(2, 1, 1).expand(2, 6, 8))
    to_camera = heights.view(2, 1, 1) * torch.sqrt(1 + x**2 + y**2)  # height / cos(angle off the axis)
    torch.testing.assert_close(data.output["distance_to_camera"].cpu()[..., 0], to_camera)
    # the principal point sits right of the image's centre: the left corner looks farther off the axis
    assert data.output["distance_to_camera"][0, 0, 0, 0] > data.output["distance_to_camera"][0, 0, -1, 0] > 2.0
    torch.testing.assert_close(data.output["normals"].cpu(), torch.tensor([0.0, 0.0, 1.0]).expand(2, 6, 8, 3))
    assert camera.frame.tolist() == [1, 1]
    assert data.info == [dict.fromkeys(["distance_to_image_plane", "normals", "distance_to_camera"])] * 2


@pytest.mark.parametrize("behaviour", ["none", "max", "zero"])
def test_level_camera_sees_ground_below_the_horizon_only(behaviour):
    """At 1 m looking along +x: pixel rows below the centre hit the ground h * fy / (v + 0.5 - cy) ahead;
    rows above miss. max_distance 10 m clips the nearest row to the horizon (18.3 m) as asked."""
    make_sim()
    create_prim("/World/Origin_00/CameraSensor", "Xform")
    offset = RayCasterCameraCfg.OffsetCfg(pos=(0.0, 0.0, 1.0), convention="world")  # forward +x, up +z
    camera = RayCasterCamera(
        camera_cfg(
            data_types=["distance_to_image_plane", "distance_to_camera"],
            offset=offset,
            max_distance=10.0,
            depth_clipping_behavior=behaviour,
        )
    )
    sim_utils.SimulationContext.instance().reset()
    plane = camera.data.output["distance_to_image_plane"][0, ..., 0]
    to_camera = camera.data.output["distance_to_camera"][0, ..., 0]
    k = camera.data.intrinsic_matrices[0]
    x, y = pixel_tangents(k, 6, 8)
    expected = 1.0 / y[3:]  # rows 3, 4, 5: 0.5, 1.5 and 2.5 pixels below the centre
    assert float(expected[0, 0]) > 10.0 > float(expected[1, 0])
    torch.testing.assert_close(plane[4:], expected[1:])
    torch.testing.assert_close(to_camera[4:], expected[1:] * torch.sqrt(1 + x[4:] ** 2 + y[4:] ** 2))
    if behaviour == "none":  # misses: nan and inf; beyond max_distance: kept
        assert torch.isnan(plane[:3]).all() and torch.isinf(to_camera[:3]).all()
        torch.testing.assert_close(plane[3], expected[0])
    else:
        fill = 10.0 if behaviour == "max" else 0.0
        assert (plane[:4] == fill).all() and (to_camera[:4] == fill).all()


def test_camera_rides_on_a_body_and_never_sees_it():
    """A cube falling from 2 m with the camera at its centre looking down: the image is the cube's height
    (the cube itself is no target), and the camera follows the cube."""
    sim = make_sim()
    cube = RigidObject(
        RigidObjectCfg(
            prim_path="/World/envs/env_.*/Cube",
            spawn=sim_utils.CuboidCfg(
                size=(0.2, 0.2, 0.2),
                rigid_props=sim_utils.RigidBodyPropertiesCfg(),
                mass_props=sim_utils.MassPropertiesCfg(mass=1.0),
                collision_props=sim_utils.CollisionPropertiesCfg(),
            ),
            init_state=RigidObjectCfg.InitialStateCfg(pos=(0.0, 0.0, 2.0)),
        )
    )
    down = RayCasterCameraCfg.OffsetCfg(rot=(0.0, 1.0, 0.0, 0.0))  # ROS: forward +z, turned half about x
    camera = RayCasterCamera(camera_cfg(offset=down).replace(prim_path="/World/envs/env_.*/Cube"))
    sim.reset()
    heights = []
    for _ in range(10):
        sim.step()
        camera.update(sim.get_physics_dt())
        cube.update(sim.get_physics_dt())
        z = float(cube.data.root_pos_w[0, 2])
        torch.testing.assert_close(camera.data.pos_w[0], cube.data.root_pos_w[0])
        torch.testing.assert_close(camera.data.output["distance_to_image_plane"][0], torch.full((6, 8, 1), z))
        heights.append(z)
    assert heights[-1] < heights[0] < 2.0  # it fell, and the image followed
    assert camera.frame.item() == 10


@pytest.mark.parametrize("device", DEVICES)
def test_in_a_scene_each_env_sees_its_own_ground_below_its_box(device):
    """A scene field like Isaac Lab's: on a box in every env (3 envs, each at its own origin), looking down
    from 0.5 m below the box's centre; the ground 0.3 m up. The image plane is 0.7 m away everywhere."""

    @configclass
    class SceneCfg(InteractiveSceneCfg):
        ground = AssetBaseCfg(
            prim_path="/World/ground",
            spawn=sim_utils.GroundPlaneCfg(),
            init_state=AssetBaseCfg.InitialStateCfg(pos=(0.0, 0.0, 0.3)),
        )
        box = RigidObjectCfg(
            prim_path="{ENV_REGEX_NS}/Box",
            spawn=sim_utils.CuboidCfg(
                size=(0.2, 0.2, 0.2), rigid_props=sim_utils.RigidBodyPropertiesCfg(kinematic_enabled=True)
            ),
            init_state=RigidObjectCfg.InitialStateCfg(pos=(0.0, 0.0, 1.5)),
        )
        camera = RayCasterCameraCfg(
            prim_path="{ENV_REGEX_NS}/Box",
            mesh_prim_paths=["/World/ground"],
            offset=RayCasterCameraCfg.OffsetCfg(pos=(0.0, 0.0, -0.5), rot=(0.0, 1.0, 0.0, 0.0)),
            data_types=["distance_to_image_plane"],
            pattern_cfg=patterns.PinholeCameraPatternCfg(**LENS),
        )

    sim = sim_utils.SimulationContext(sim_utils.SimulationCfg(device=device))
    scene = InteractiveScene(SceneCfg(num_envs=3, env_spacing=4.0))
    sim.reset()
    sim.step()
    scene.update(sim.get_physics_dt())
    camera = scene["camera"]
    torch.testing.assert_close(camera.data.pos_w, scene.env_origins + torch.tensor([0.0, 0.0, 1.0], device=device))
    torch.testing.assert_close(
        camera.data.output["distance_to_image_plane"], torch.full((3, 6, 8, 1), 0.7, device=device)
    )
    scene.reset(torch.tensor([False, True, False], device=device))
    assert camera.frame.tolist() == [1, 0, 1]


def test_debug_markers_sample_a_grid_of_hits_across_the_image():
    """640 x 480 rays per camera: 32 x 32 markers each, spread over the image (the nearest row's too)."""
    sim = make_sim()
    create_prim("/World/Origin_00/CameraSensor", "Xform")
    create_prim("/World/Origin_01/CameraSensor", "Xform")
    lens = patterns.PinholeCameraPatternCfg(width=640, height=480)
    camera = RayCasterCamera(camera_cfg(pattern_cfg=lens, debug_vis=True))
    sim.reset()
    camera.set_world_poses_from_view(torch.tensor([[2.5, 2.5, 2.5]] * 2), torch.zeros(2, 3))
    sim.run_render_callbacks()
    assert camera.ray_visualizer.count == 2 * 32 * 32
    hits = camera.ray_hits_w.view(2, 480, 640, 3)
    assert camera.ray_visualizer._translations[-1].tolist() == hits[1, 472, 630].tolist()  # rows 7 + 15 k


def test_camera_env_ids_are_ids_in_their_order_or_the_ids_a_mask_selects():
    """The one helper Camera and RayCasterCamera turn env_ids into camera indices with: given ids keep
    their order (the poses given with them match it); a mask, slice or None select ascending ids."""
    from simlab.utils.env_mask import env_ids_in_order

    for env_ids, expected in (
        ([2, 0, 2], [2, 0, 2]),
        (torch.tensor([[1], [0]]), [1, 0]),
        (torch.tensor([True, False, True]), [0, 2]),
        (slice(1, None), [1, 2]),
        (None, [0, 1, 2]),
    ):
        ids = env_ids_in_order(env_ids, 3, "cpu")
        assert ids.dtype == torch.long and ids.tolist() == expected


def test_set_world_poses_in_each_convention_reads_back():
    sim = make_sim()
    create_prim("/World/Origin_00/CameraSensor", "Xform", translation=(1.0, 2.0, 0.0))
    camera = RayCasterCamera(camera_cfg())
    sim.reset()
    quat_ros = torch.tensor([[-0.17591989, 0.33985114, 0.82047325, -0.42470819]])  # Isaac Lab's tutorial's
    camera.set_world_poses(torch.tensor([[2.5, 2.5, 2.5]]), quat_ros, convention="ros")
    torch.testing.assert_close(camera.data.pos_w, torch.tensor([[2.5, 2.5, 2.5]]))
    same = torch.sign(camera.data.quat_w_ros[0, 0]) * torch.sign(quat_ros[0, 0])
    torch.testing.assert_close(camera.data.quat_w_ros * same, quat_ros, atol=1e-5, rtol=0)
    camera.reset(torch.tensor([True]))  # a bool mask, as the scene resets
    assert camera.frame.item() == 0
    torch.testing.assert_close(camera.data.pos_w, torch.tensor([[2.5, 2.5, 2.5]]))  # the offset stays


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ({"data_types": ["rgb"]}, "need a renderer"),
        ({"data_types": ["depth_image"]}, "unknown types ['depth_image']"),
        ({"drift_range": (-0.1, 0.1)}, "takes no drift"),
        ({"pattern_cfg": patterns.GridPatternCfg(resolution=0.1, size=(1.0, 1.0))}, "PinholeCameraPatternCfg"),
        ({"pattern_cfg": patterns.PinholeCameraPatternCfg(width=0, height=4)}, "width must be a positive"),
        ({"depth_clipping_behavior": "clip"}, "'max', 'zero' or 'none'"),
    ],
)
def test_what_rays_cannot_give_is_refused_in_one_line(change, message):
    make_sim()
    with pytest.raises(ValueError, match=None) as error:
        RayCasterCamera(camera_cfg(**change))
    assert message in str(error.value) and "\n" not in str(error.value)


def test_basic_writer_writes_each_annotator_as_replicator_lays_it_out(tmp_path):
    depth = np.arange(20, dtype=np.float32).reshape(4, 5, 1)
    normals = np.zeros((4, 5, 3), np.float32)
    normals[..., 2] = 1.0
    normals[0, 0] = np.inf  # nothing hit
    rgb = np.full((4, 5, 3), 7, np.uint8)
    writer = BasicWriter(output_dir=str(tmp_path / "out"), frame_padding=3, colorize_depth=True)
    data = {
        "annotators": {
            "distance_to_image_plane": {"render_product": {"data": depth}},
            "normals": {"render_product": {"data": normals}},
            "rgb": {"render_product": {"data": rgb, "idToLabels": {1: "cube"}}},
        },
        "trigger_outputs": {"on_time": torch.tensor(2)},
    }
    writer.write(data)
    paths = writer.write(data)
    names = sorted(p.rsplit("/", 1)[1] for p in paths)
    assert names == [
        "distance_to_image_plane_2_001.npy",
        "distance_to_image_plane_2_001.png",
        "normals_2_001.png",
        "rgb_2_001.json",
        "rgb_2_001.png",
    ]
    import imageio.v3 as iio

    out = tmp_path / "out"
    np.testing.assert_array_equal(np.load(out / "distance_to_image_plane_2_000.npy"), depth)
    grey = iio.imread(out / "distance_to_image_plane_2_000.png")
    assert grey.shape == (4, 5) and grey[-1, -1] == 255 and grey[0, 1] == round(255 / 19)  # depth / deepest
    colours = iio.imread(out / "normals_2_000.png")
    assert colours[1, 1].tolist() == [128, 128, 255] and colours[0, 0].tolist() == [0, 0, 0]  # (n + 1) / 2
    np.testing.assert_array_equal(iio.imread(out / "rgb_2_000.png"), rgb)
    assert (out / "rgb_2_000.json").read_text() == '{"idToLabels": {"1": "cube"}}'
    with pytest.raises(NotImplementedError, match="no Kit render products"):
        writer.attach(["/Render/RenderProduct"])
    with pytest.raises(ValueError, match="Replicator's layout"):
        writer.write({"distance_to_image_plane": depth})
    for wrong in (depth, {"render_product": depth}, {"render_product": {"array": depth}}):
        with pytest.raises(ValueError, match=r"annotator 'normals' must map render products to \{'data': array"):
            writer.write({"annotators": {"rgb": {"render_product": {"data": rgb}}, "normals": wrong}})
    assert not (out / "rgb_2_002.png").exists()  # nothing written from a refused write
    with pytest.raises(TypeError, match=r"unknown arguments \['outputdir'\]"):
        BasicWriter(output_dir=str(tmp_path), outputdir="x")


def test_basic_writer_refuses_names_that_leave_its_output_folder(tmp_path):
    """A render product or annotator named '../x' would write beside output_dir: refused, nothing written."""
    writer = BasicWriter(output_dir=str(tmp_path / "out"))
    rgb = np.full((2, 2, 3), 7, np.uint8)
    for products in ({"left": {"data": rgb}, "../escaped": {"data": rgb}}, {"render_product": {"data": rgb}}):
        annotator = "rgb" if "left" in products else "../escaped_rgb"
        with pytest.raises(ValueError, match="must be plain file names") as caught:
            writer.write({"annotators": {annotator: products}})
        assert "\n" not in str(caught.value)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]
    assert list((tmp_path / "out").iterdir()) == []


def test_pinhole_pattern_rays_project_back_to_their_pixel_centres():
    """Each ray, put through the intrinsics, lands on the centre of its pixel (row by row)."""
    lens = patterns.PinholeCameraPatternCfg(**LENS, vertical_aperture=10.0, vertical_aperture_offset=-0.05)
    k = torch.tensor(lens.intrinsic_matrix()).unsqueeze(0)
    starts, directions = lens.func(lens, k, "cpu")
    assert starts.shape == directions.shape == (1, 48, 3) and (starts == 0).all()
    torch.testing.assert_close(directions.norm(dim=-1), torch.ones(1, 48))
    optical = torch.stack([-directions[..., 1], -directions[..., 2], directions[..., 0]], dim=-1)  # ROS axes
    pixels = optical @ k[0].T
    pixels = pixels[..., :2] / pixels[..., 2:]
    v, u = torch.meshgrid(torch.arange(6) + 0.5, torch.arange(8) + 0.5, indexing="ij")
    torch.testing.assert_close(pixels[0], torch.stack([u.reshape(-1), v.reshape(-1)], dim=-1))
    assert math.isclose(k[0, 1, 1].item(), 6 * 24.0 / 10.0, rel_tol=1e-6)
    assert math.isclose(k[0, 1, 2].item(), -0.05 * 6 * 24.0 / 10.0 + 3.0, rel_tol=1e-6)


class _HostReads(torch.overrides.TorchFunctionMode):
    """Records the torch calls that read a tensor's values back to the host (a sync on the GPU)."""

    READS = ("nonzero", "item", "tolist", "__bool__", "numpy", "cpu", "unique", "argwhere")

    def __init__(self):
        super().__init__()
        self.calls: list[str] = []

    def __torch_function__(self, func, types, args=(), kwargs=None):
        name = getattr(func, "__name__", "")
        if name in self.READS:
            self.calls.append(name)
        return func(*args, **(kwargs or {}))


def test_a_masked_reset_reads_nothing_back_to_the_host():
    """The scene resets sensors with a bool mask inside the env step, which a CUDA graph captures: the
    camera's reset must not turn the mask into ids (nonzero reads the device back)."""
    sim = make_sim()
    create_prim("/World/Origin_00/CameraSensor", "Xform")
    create_prim("/World/Origin_01/CameraSensor", "Xform", translation=(5.0, 0.0, 0.0))
    camera = RayCasterCamera(camera_cfg())
    sim.reset()
    camera.set_world_poses_from_view(torch.tensor([[0.0, 0.0, 2.0], [5.0, 0.0, 2.0]]), torch.zeros(2, 3))
    camera.data  # noqa: B018 - casts: frame 1 in both
    with _HostReads() as reads:
        camera.reset(torch.tensor([False, True]))
    assert reads.calls == []
    assert camera.frame.tolist() == [1, 0]
    camera.reset([0])  # ids still work
    assert camera.frame.tolist() == [0, 0]
