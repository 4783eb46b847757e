"""Cameras under create_prim groups sharing one world (Isaac Lab's camera tutorial), placed with
set_world_poses(_from_view), and the normals and instance images, against a 0.4 m box on the ground
seen from above and from the side."""

from __future__ import annotations

import pytest
import torch
from conftest import rendering_available

import simlab.sim as sim_utils
from simlab.sensors import Camera, CameraCfg
from simlab.sim.utils import create_prim

pytestmark = pytest.mark.skipif(not rendering_available(), reason="no offscreen OpenGL backend (libosmesa6 or EGL)")

TYPES = ["rgb", "distance_to_image_plane", "normals", "instance_id_segmentation_fast", "instance_segmentation_fast"]


def box_and_two_cameras(**cfg) -> tuple[sim_utils.SimulationContext, Camera]:
    sim = sim_utils.SimulationContext(sim_utils.SimulationCfg(device="cpu"))
    ground = sim_utils.GroundPlaneCfg()
    ground.func("/World/ground", ground)
    box = sim_utils.CuboidCfg(size=(0.4, 0.4, 0.4))
    box.func("/World/Box", box, translation=(0.0, 0.0, 0.2))
    create_prim("/World/Origin_00", "Xform")
    create_prim("/World/Origin_01", "Xform")
    camera = Camera(CameraCfg(prim_path="/World/Origin_.*/CameraSensor", width=32, height=24, **cfg))
    sim.reset()
    return sim, camera


def test_two_cameras_in_one_world_see_the_box_from_above_and_from_the_side():
    sim, camera = box_and_two_cameras(
        data_types=TYPES, colorize_instance_id_segmentation=False, colorize_instance_segmentation=False
    )
    assert sim.num_envs == 1 and camera.num_instances == 2
    eyes = torch.tensor([[0.0, 0.0, 2.0], [2.0, 0.0, 0.2]])
    camera.set_world_poses_from_view(eyes, torch.tensor([[0.0, 0.0, 0.0], [0.0, 0.0, 0.2]]))
    sim.step()
    camera.update(sim.get_physics_dt())
    data = camera.data
    assert data.output["rgb"].shape == (2, 24, 32, 3) and data.output["normals"].shape == (2, 24, 32, 3)
    torch.testing.assert_close(data.pos_w, eyes)
    # the centre pixel: the box's top 1.6 m below the first camera, its +x face 1.8 m before the second
    centre = data.output["distance_to_image_plane"][:, 12, 16, 0]
    torch.testing.assert_close(centre, torch.tensor([1.6, 1.8]), atol=1e-3, rtol=0)
    torch.testing.assert_close(data.output["normals"][:, 12, 16], torch.tensor([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0]]))
    torch.testing.assert_close(data.output["normals"][0, 0, 0], torch.tensor([0.0, 0.0, 1.0]))  # the ground
    assert (data.output["normals"][1, 0] == 0).all()  # the second camera's top row sees the sky: no normal
    # ids: the box's geom and body where it is seen, the ground's around it
    box_geom = [
        g for g, name in data.info[0]["instance_id_segmentation_fast"]["idToLabels"].items() if name == "Box/geom"
    ]
    assert data.output["instance_id_segmentation_fast"][0, 12, 16, 0].item() == box_geom[0]
    assert (
        data.info[1]["instance_segmentation_fast"]["idToLabels"][
            data.output["instance_segmentation_fast"][1, 12, 16, 0].item()
        ]
        == "Box/body"
    )
    assert data.info[0]["rgb"] is None and len(data.info) == 2


def test_colourised_instances_are_labelled_by_colour():
    sim, camera = box_and_two_cameras(data_types=["instance_id_segmentation_fast"])
    camera.set_world_poses(torch.tensor([[0.0, 0.0, 2.0]]), torch.tensor([[0.0, 1.0, 0.0, 0.0]]), env_ids=[0])
    image = camera.data.output["instance_id_segmentation_fast"][0]
    labels = camera.data.info[0]["instance_id_segmentation_fast"]["idToLabels"]
    assert labels[str(tuple(image[12, 16].tolist()))] == "Box/geom"  # ROS: (0, 1, 0, 0) looks straight down
    assert labels[str(tuple(image[0, 0].tolist()))] == "ground"


def test_groups_that_are_not_the_worlds_are_refused():
    sim = sim_utils.SimulationContext(sim_utils.SimulationCfg(device="cpu"))
    sim.num_envs = 3
    create_prim("/World/Origin_00", "Xform")
    create_prim("/World/Origin_01", "Xform")
    Camera(CameraCfg(prim_path="/World/Origin_.*/CameraSensor", width=8, height=6))
    with pytest.raises(ValueError, match="matches 2 create_prim groups but the simulation has 3 worlds"):
        sim.reset()


def test_a_camera_in_every_env_frame_moves_in_all_envs_at_once():
    """One MJCF camera serves every env's frame: set_world_poses takes one pose relative to the env origins."""
    from simlab.scene import InteractiveScene, InteractiveSceneCfg
    from simlab.utils import configclass

    @configclass
    class SceneCfg(InteractiveSceneCfg):
        camera = CameraCfg(prim_path="{ENV_REGEX_NS}/Camera", width=8, height=6, data_types=["distance_to_image_plane"])

    sim = sim_utils.SimulationContext(sim_utils.SimulationCfg(device="cpu"))
    ground = sim_utils.GroundPlaneCfg()
    ground.func("/World/ground", ground)
    scene = InteractiveScene(SceneCfg(num_envs=2, env_spacing=4.0))
    sim.reset()
    camera, origins = scene["camera"], scene.env_origins
    down = torch.tensor([[0.0, 1.0, 0.0, 0.0]] * 2)  # ROS: looking along -z
    camera.set_world_poses(origins + torch.tensor([0.0, 0.0, 1.5]), down)
    torch.testing.assert_close(
        camera.data.output["distance_to_image_plane"], torch.full((2, 6, 8, 1), 1.5), atol=1e-3, rtol=0
    )
    torch.testing.assert_close(camera.data.pos_w, origins + torch.tensor([0.0, 0.0, 1.5]))
    with pytest.raises(ValueError, match="give a pose for every env"):
        camera.set_world_poses(origins[:1] + 1.0, env_ids=[0])
    with pytest.raises(ValueError, match="takes one pose relative to the env origin"):
        camera.set_world_poses(torch.tensor([[0.0, 0.0, 1.0], [0.0, 0.0, 2.0]]) + origins)
