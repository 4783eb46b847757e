"""Sensors against values computed here: ray casts on known terrain (a raised plane, box stairs and
grids, height fields) against a brute-force reference from the terrain generator's own heights; the
IMU on a box in free fall, at rest and spinning; contact air and contact times of a dropped box."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest
import torch
from conftest import DEVICES
from test_terrains import small_terrain

import simlab.sim as sim_utils
from simlab.assets import AssetBaseCfg, RigidObjectCfg
from simlab.envs import ManagerBasedRLEnv, ManagerBasedRLEnvCfg, mdp
from simlab.managers import EventTermCfg, SceneEntityCfg
from simlab.managers import ObservationGroupCfg as ObsGroup
from simlab.managers import ObservationTermCfg as ObsTerm
from simlab.managers import RewardTermCfg as RewTerm
from simlab.managers import TerminationTermCfg as DoneTerm
from simlab.robots.ant import ANT_CFG
from simlab.scene import InteractiveScene, InteractiveSceneCfg
from simlab.sensors import ContactSensorCfg, ImuCfg, RayCasterCfg, patterns
from simlab.terrains import TerrainImporterCfg
from simlab.terrains.box_terrains import boxes_to_heights
from simlab.terrains.terrain_generator import TerrainGenerator
from simlab.utils import configclass
from simlab.utils.errors import ConfigError
from simlab.utils.math import quat_apply_yaw, quat_from_euler_xyz

DT = 0.005
PLANE_HEIGHT = 0.3
GRID = patterns.GridPatternCfg(resolution=0.1, size=(1.6, 1.0))


def box_cfg(prim_path: str, z: float, size: float = 0.2) -> RigidObjectCfg:
    return RigidObjectCfg(
        prim_path=prim_path,
        spawn=sim_utils.CuboidCfg(
            size=(size, size, size),
            rigid_props=sim_utils.RigidBodyPropertiesCfg(),
            mass_props=sim_utils.MassPropertiesCfg(mass=1.0),
        ),
        init_state=RigidObjectCfg.InitialStateCfg(pos=(0.0, 0.0, z)),
    )


def scanner_cfg(**kw) -> RayCasterCfg:
    """Isaac Lab's locomotion height scanner (velocity_env_cfg), on the box."""
    cfg = RayCasterCfg(
        prim_path="{ENV_REGEX_NS}/Robot",
        offset=RayCasterCfg.OffsetCfg(pos=(0.0, 0.0, 20.0)),
        ray_alignment="yaw",
        pattern_cfg=GRID,
        mesh_prim_paths=["/World/ground"],
    )
    return cfg.replace(**kw)


def make_scene(scene_cfg: InteractiveSceneCfg, device: str = "cpu", gravity=(0.0, 0.0, -9.81)):
    sim = sim_utils.SimulationContext(sim_utils.SimulationCfg(dt=DT, device=device, gravity=gravity))
    scene = InteractiveScene(scene_cfg)
    sim.reset()
    return sim, scene


def place(sim, scene, name: str, pos: torch.Tensor, quat: torch.Tensor) -> None:
    """Put the rigid object ``name`` at world poses, at rest, and update the sensors."""
    obj = scene[name]
    obj.write_root_pose_to_sim(torch.cat([pos, quat], dim=-1).to(sim.device))
    obj.write_root_velocity_to_sim(torch.zeros(scene.num_envs, 6, device=sim.device))
    sim.forward()
    scene.update(DT)


# -- ray caster -----------------------------------------------------------------------------------


@configclass
class PlaneSceneCfg(InteractiveSceneCfg):
    ground = AssetBaseCfg(
        prim_path="/World/ground",
        spawn=sim_utils.GroundPlaneCfg(),
        init_state=AssetBaseCfg.InitialStateCfg(pos=(0.0, 0.0, PLANE_HEIGHT)),
    )
    robot = box_cfg("{ENV_REGEX_NS}/Robot", z=2.0)
    # a second object right under the sensor: not in mesh_prim_paths, so never hit
    obstacle = box_cfg("{ENV_REGEX_NS}/Obstacle", z=1.0, size=0.5)
    height_scanner = scanner_cfg()


@pytest.mark.parametrize("device", DEVICES)
def test_height_scan_over_a_raised_plane(device):
    """Every ray hits the plane at its height, below its own start, in every env (each env has its
    own origin); the other objects are not hit; Isaac Lab's height_scan formula gives the height."""
    n = 3
    sim, scene = make_scene(PlaneSceneCfg(num_envs=n, env_spacing=4.0), device)
    yaw = torch.tensor([0.0, 0.7, -2.0])
    quat = quat_from_euler_xyz(torch.zeros(n), torch.zeros(n), yaw)
    base = scene.env_origins.cpu() + torch.tensor([0.1, -0.2, 2.0])
    place(sim, scene, "robot", base, quat)
    place(sim, scene, "obstacle", base - torch.tensor([0.0, 0.0, 1.0]), torch.tensor([[1.0, 0, 0, 0]] * n))
    sensor = scene["height_scanner"]
    hits = sensor.data.ray_hits_w.cpu()
    assert hits.shape == (n, 17 * 11, 3)
    torch.testing.assert_close(hits[..., 2], torch.full((n, 187), PLANE_HEIGHT), atol=1e-4, rtol=0)
    # yaw alignment: the grid turns with the heading, under the base
    starts, _ = patterns.grid_pattern(GRID, "cpu")
    expected_xy = (base.unsqueeze(1) + quat_apply_yaw(quat.unsqueeze(1), starts.expand(n, -1, -1)))[..., :2]
    torch.testing.assert_close(hits[..., :2], expected_xy, atol=1e-4, rtol=0)
    torch.testing.assert_close(sensor.data.pos_w.cpu(), base, atol=1e-5, rtol=0)
    height_scan = sensor.data.pos_w[:, 2].unsqueeze(1) - sensor.data.ray_hits_w[..., 2] - 0.5
    torch.testing.assert_close(height_scan.cpu(), torch.full((n, 187), 2.0 - PLANE_HEIGHT - 0.5), atol=1e-4, rtol=0)


def test_grid_pattern_ordering_and_alignments():
    """Isaac Lab's orderings ("xy": x fastest) and alignments ("world" keeps the grid on the world
    axes, "base" tilts starts and directions with the body)."""
    cfg = patterns.GridPatternCfg(resolution=1.0, size=(2.0, 1.0))
    xy, _ = patterns.grid_pattern(cfg, "cpu")
    yx, _ = patterns.grid_pattern(cfg.replace(ordering="yx"), "cpu")
    assert xy[:4, :2].tolist() == [[-1, -0.5], [0, -0.5], [1, -0.5], [-1, 0.5]]
    assert yx[:4, :2].tolist() == [[-1, -0.5], [-1, 0.5], [0, -0.5], [0, 0.5]]
    with pytest.raises(ValueError, match="ordering must be one of"):
        patterns.grid_pattern(cfg.replace(ordering="zz"), "cpu")

    @configclass
    class SceneCfg(PlaneSceneCfg):
        obstacle = None
        height_scanner = scanner_cfg(ray_alignment="world", offset=RayCasterCfg.OffsetCfg(pos=(0.0, 0.0, 0.0)))
        tilted_scanner = scanner_cfg(ray_alignment="base", offset=RayCasterCfg.OffsetCfg(pos=(0.0, 0.0, 0.0)))

    sim, scene = make_scene(SceneCfg(num_envs=1, env_spacing=4.0))
    pitch = 0.3
    quat = quat_from_euler_xyz(torch.zeros(1), torch.tensor([pitch]), torch.tensor([1.0]))
    place(sim, scene, "robot", torch.tensor([[0.0, 0.0, 2.0]]), quat)
    world = scene["height_scanner"].data.ray_hits_w[0]
    starts, _ = patterns.grid_pattern(GRID, "cpu")
    torch.testing.assert_close(world[:, :2], starts[:, :2], atol=1e-4, rtol=0)
    # "base": the central ray leaves along the tilted -z axis: it lands (h tan(pitch)) ahead in the heading
    tilted = scene["tilted_scanner"].data.ray_hits_w[0]
    centre = tilted[len(tilted) // 2]
    drop = 2.0 - PLANE_HEIGHT
    heading = torch.tensor([math.cos(1.0), math.sin(1.0)])
    torch.testing.assert_close(centre[:2], -heading * drop * math.tan(pitch), atol=1e-4, rtol=0)


def test_misses_are_inf_and_max_distance_counts():
    @configclass
    class SceneCfg(PlaneSceneCfg):
        obstacle = None
        height_scanner = scanner_cfg(max_distance=10.0)  # starts 20 m up: beyond reach
        sideways = scanner_cfg(
            pattern_cfg=patterns.GridPatternCfg(resolution=1.0, size=(0.0, 0.0), direction=(0.0, 0.0, 1.0))
        )

    sim, scene = make_scene(SceneCfg(num_envs=2, env_spacing=4.0))
    scene.update(DT)
    assert torch.isinf(scene["height_scanner"].data.ray_hits_w).all()
    assert torch.isinf(scene["sideways"].data.ray_hits_w).all()  # straight up: nothing there
    scan = scene["height_scanner"].data.pos_w[:, 2:3] - scene["height_scanner"].data.ray_hits_w[..., 2] - 0.5
    assert (scan.clip(-1.0, 1.0) == -1.0).all()  # Isaac Lab's height_scan term clips to (-1, 1)


def hfield_height(heights: np.ndarray, size: tuple[float, float], x: float, y: float) -> float:
    """Height of MuJoCo's height-field surface (two triangles per cell, split along the diagonal from
    the (x-, y-) to the (x+, y+) corner) at (x, y) in the tile frame; ``heights`` indexed [x, y]."""
    nx, ny = heights.shape
    u, v = x / size[0] * (nx - 1), y / size[1] * (ny - 1)
    i, j = min(int(u), nx - 2), min(int(v), ny - 2)
    fx, fy = u - i, v - j
    h00, h10, h01, h11 = heights[i, j], heights[i + 1, j], heights[i, j + 1], heights[i + 1, j + 1]
    if fx >= fy:
        return h00 + fx * (h10 - h00) + fy * (h11 - h10)
    return h00 + fy * (h01 - h00) + fx * (h11 - h01)


def reference_height(terrain: TerrainGenerator, x: float, y: float) -> float:
    """The highest terrain surface over (x, y), from the generator's heights and boxes (brute force);
    tiles of several boxes are height fields of their sampled tops unless built as boxes."""
    top = -math.inf
    boxes = [(c, s) for c, s in terrain.border_boxes]
    for tile in terrain.tiles:
        shift = np.array([*tile.corner, 0.0])
        heights = tile.geometry.heights
        if len(tile.geometry.boxes) > 1 and terrain.cfg.box_tiles_as == "height_field":
            heights = boxes_to_heights(tile.geometry.boxes, terrain.cfg.size, terrain.cfg.horizontal_scale)
        else:
            boxes += [(c + shift, s) for c, s in tile.geometry.boxes]
        lx, ly = x - tile.corner[0], y - tile.corner[1]
        if heights is not None and 0 <= lx <= terrain.cfg.size[0] and 0 <= ly <= terrain.cfg.size[1]:
            top = max(top, hfield_height(heights, terrain.cfg.size, lx, ly))
    for centre, size in boxes:
        if abs(x - centre[0]) <= size[0] / 2 and abs(y - centre[1]) <= size[1] / 2:
            top = max(top, centre[2] + size[2] / 2)
    return top


@pytest.mark.parametrize("box_tiles_as", ["height_field", "boxes"])
@pytest.mark.parametrize("device", DEVICES)
def test_height_scan_on_generated_terrain_matches_brute_force(device, box_tiles_as):
    """Robots at random places and headings over every sub-terrain kind (stairs, boxes, rough,
    slopes): each hit lies on the terrain surface computed from the generator's own data."""
    n = 16

    @configclass
    class SceneCfg(InteractiveSceneCfg):
        terrain = TerrainImporterCfg(
            prim_path="/World/ground",
            terrain_type="generator",
            terrain_generator=small_terrain(box_tiles_as=box_tiles_as),
        )
        robot = box_cfg("{ENV_REGEX_NS}/Robot", z=2.0)
        height_scanner = scanner_cfg(pattern_cfg=patterns.GridPatternCfg(resolution=0.15, size=(1.2, 0.9)))

    sim, scene = make_scene(SceneCfg(num_envs=n, env_spacing=2.0), device)
    terrain = scene.terrain.terrain_generator
    g = torch.Generator().manual_seed(1)
    half = torch.tensor([terrain.cfg.num_rows * terrain.cfg.size[0], terrain.cfg.num_cols * terrain.cfg.size[1]]) / 2
    xy = (torch.rand(n, 2, generator=g) * 2 - 1) * (half - 1.0)
    pos = torch.cat([xy, torch.full((n, 1), 2.0)], dim=-1)
    quat = quat_from_euler_xyz(torch.zeros(n), torch.zeros(n), torch.rand(n, generator=g) * 6.28)
    place(sim, scene, "robot", pos, quat)
    hits = scene["height_scanner"].data.ray_hits_w.cpu().double()
    assert torch.isfinite(hits).all()
    expected = torch.tensor([[reference_height(terrain, float(x), float(y)) for x, y in env[:, :2]] for env in hits])
    kinds = {tile.kind for tile in terrain.tiles}
    assert {"stairs", "boxes", "rough", "slope"} <= kinds
    torch.testing.assert_close(hits[..., 2], expected.double(), atol=2e-4, rtol=0)


def test_ray_caster_bad_input_is_named():
    def build(**kw):
        @configclass
        class SceneCfg(PlaneSceneCfg):
            height_scanner = scanner_cfg(**kw)

        make_scene(SceneCfg(num_envs=1, env_spacing=4.0))

    with pytest.raises(ValueError, match=r"mesh_prim_paths is empty"):
        build(mesh_prim_paths=[])
    with pytest.raises(ValueError, match=r"'/World/terrain' names no geom.*static geometry there: \['/World/ground'\]"):
        build(mesh_prim_paths=["/World/terrain"])
    with pytest.raises(ValueError, match=r"moving bodies.*static geometry only"):
        build(mesh_prim_paths=["{ENV_REGEX_NS}/Obstacle"])
    with pytest.raises(ValueError, match=r"matches no body of the model; bodies in the model: \['Robot/body'") as e:
        build(prim_path="{ENV_REGEX_NS}/Robot/base")
    assert "create_prim" not in str(e.value)
    with pytest.raises(ValueError, match=r"or create its Xform groups first \(sim_utils.create_prim"):
        build(prim_path="/World/Origin_.*/Scanner")  # Isaac Lab's tutorials' groups, not made yet
    with pytest.raises(ValueError, match=r"ray_alignment='up' is not one of"):
        build(ray_alignment="up")


def test_ray_caster_drift_is_drawn_per_env_and_reset_by_mask():
    @configclass
    class SceneCfg(PlaneSceneCfg):
        obstacle = None
        height_scanner = scanner_cfg(drift_range=(-0.1, 0.1), ray_cast_drift_range={"z": (0.2, 0.3)})

    sim, scene = make_scene(SceneCfg(num_envs=4, env_spacing=4.0))
    sensor = scene["height_scanner"]
    drift, z_drift = sensor.drift.clone(), sensor.ray_cast_drift[:, 2].clone()
    assert (drift.abs() <= 0.1).all() and len(set(drift[:, 0].tolist())) == 4
    scene.update(DT)
    hit_z = sensor.data.ray_hits_w[..., 2]
    torch.testing.assert_close(hit_z, (PLANE_HEIGHT + z_drift).unsqueeze(1).expand_as(hit_z), atol=1e-4, rtol=0)
    scene.reset(torch.tensor([False, True, False, True]))
    assert torch.equal(sensor.drift[[0, 2]], drift[[0, 2]]) and not torch.equal(sensor.drift[[1, 3]], drift[[1, 3]])
    # the next read casts again (as Isaac Lab's outdated buffers): the new drifts show without an update
    new_z = (PLANE_HEIGHT + sensor.ray_cast_drift[:, 2]).unsqueeze(1).expand_as(hit_z)
    torch.testing.assert_close(sensor.data.ray_hits_w[..., 2], new_z, atol=1e-4, rtol=0)
    torch.testing.assert_close(
        sensor.data.pos_w[:, :2], scene.env_origins[:, :2] + sensor.drift[:, :2], atol=1e-4, rtol=0
    )


# -- IMU --------------------------------------------------------------------------------------------


@configclass
class ImuSceneCfg(InteractiveSceneCfg):
    ground = AssetBaseCfg(prim_path="/World/ground", spawn=sim_utils.GroundPlaneCfg())
    robot = box_cfg("{ENV_REGEX_NS}/Robot", z=2.0)
    imu = ImuCfg(prim_path="{ENV_REGEX_NS}/Robot")


@pytest.mark.parametrize("device", DEVICES)
def test_imu_in_free_fall_and_at_rest(device):
    sim, scene = make_scene(ImuSceneCfg(num_envs=2, env_spacing=3.0), device)
    imu = scene["imu"]
    for _ in range(20):
        sim.step()
        scene.update(DT)
    d = imu.data
    torch.testing.assert_close(d.lin_acc_b.cpu(), torch.zeros(2, 3), atol=1e-3, rtol=0)  # free fall: 0 with the bias
    torch.testing.assert_close(d.lin_vel_b[:, 2].cpu(), torch.full((2,), -9.81 * 20 * DT), atol=0.02, rtol=0)
    torch.testing.assert_close(d.projected_gravity_b.cpu(), torch.tensor([[0.0, 0, -1]] * 2), atol=1e-5, rtol=0)
    torch.testing.assert_close(d.pos_w.cpu(), scene["robot"].data.root_pos_w.cpu(), atol=1e-5, rtol=0)
    for _ in range(400):  # lands and settles
        sim.step()
        scene.update(DT)
    d = imu.data  # read after the updates: computed now (Isaac Lab's lazy data)
    torch.testing.assert_close(d.lin_acc_b.cpu(), torch.tensor([[0.0, 0, 9.81]] * 2), atol=0.05, rtol=0)
    torch.testing.assert_close(d.lin_vel_b.cpu(), torch.zeros(2, 3), atol=1e-3, rtol=0)
    # Isaac Lab's IMU observation terms read the same data
    env = SimpleNamespace(scene=scene)
    for term, field in [("imu_lin_acc", "lin_acc_b"), ("imu_ang_vel", "ang_vel_b"), ("imu_orientation", "quat_w"),
                        ("imu_projected_gravity", "projected_gravity_b")]:  # fmt: skip
        torch.testing.assert_close(getattr(mdp, term)(env), getattr(d, field))


@pytest.mark.parametrize("device", DEVICES)
def test_imu_on_a_spinning_body_reads_the_offset_point(device):
    """Without gravity, a body spinning at w about z: an IMU r along x (turned 90 deg about z) moves
    at w r and accelerates at w^2 r towards the axis, both read in the IMU's own frame."""
    w, r = 2.0, 0.5

    @configclass
    class SceneCfg(ImuSceneCfg):
        ground = None
        imu = ImuCfg(
            prim_path="{ENV_REGEX_NS}/Robot",
            offset=ImuCfg.OffsetCfg(pos=(r, 0.0, 0.0), rot=(math.cos(math.pi / 4), 0.0, 0.0, math.sin(math.pi / 4))),
            gravity_bias=(0.0, 0.0, 0.0),
        )

    sim, scene = make_scene(SceneCfg(num_envs=1, env_spacing=3.0), device, gravity=(0.0, 0.0, 0.0))
    scene["robot"].write_root_velocity_to_sim(torch.tensor([[0.0, 0, 0, 0, 0, w]], device=sim.device))
    for _ in range(10):
        sim.step()
        scene.update(DT)
    d = scene["imu"].data
    # the IMU's x axis is the body's y (tangential velocity w r), its y axis the body's -x (towards the axis)
    torch.testing.assert_close(d.lin_vel_b.cpu(), torch.tensor([[w * r, 0.0, 0.0]]), atol=1e-3, rtol=0)
    torch.testing.assert_close(d.lin_acc_b.cpu(), torch.tensor([[0.0, w * w * r, 0.0]]), atol=1e-2, rtol=0)
    torch.testing.assert_close(d.ang_vel_b.cpu(), torch.tensor([[0.0, 0.0, w]]), atol=1e-4, rtol=0)
    torch.testing.assert_close(d.ang_acc_b.cpu(), torch.zeros(1, 3), atol=1e-3, rtol=0)


def test_imu_on_a_missing_body_lists_the_bodies():
    @configclass
    class SceneCfg(ImuSceneCfg):
        imu = ImuCfg(prim_path="{ENV_REGEX_NS}/Robot/imu_link")

    with pytest.raises(ValueError, match=r"matches no body.*Bodies in the model: \['Robot/body'\]"):
        make_scene(SceneCfg(num_envs=1, env_spacing=3.0))


# -- contact sensor ---------------------------------------------------------------------------------


@configclass
class DropSceneCfg(InteractiveSceneCfg):
    ground = AssetBaseCfg(prim_path="/World/ground", spawn=sim_utils.GroundPlaneCfg())
    robot = box_cfg("{ENV_REGEX_NS}/Robot", z=0.3)
    contacts = ContactSensorCfg(prim_path="{ENV_REGEX_NS}/Robot/.*", history_length=3, track_air_time=True)


def test_contact_sensor_counts_air_then_contact_time_and_resets_by_mask():
    """A box dropped from 0.3 m: air time grows by dt each step until it lands (free fall of
    0.2 m: ~0.2 s), then contact time grows; first contact is reported once; history keeps the
    newest first; a reset by mask clears only those envs."""
    sim, scene = make_scene(DropSceneCfg(num_envs=2, env_spacing=3.0))
    sensor = scene["contacts"]
    d = sensor.data
    air_steps = 0
    for _ in range(200):
        sim.step()
        scene.update(DT)
        if (d.current_contact_time > 0).any():
            break
        air_steps += 1
        torch.testing.assert_close(d.current_air_time, torch.full((2, 1), air_steps * DT))
    fall = math.sqrt(2 * 0.2 / 9.81)
    assert abs(air_steps * DT - fall) < 0.02, (air_steps * DT, fall)
    assert sensor.compute_first_contact(DT).all()
    torch.testing.assert_close(d.last_air_time, torch.full((2, 1), (air_steps + 1) * DT))
    assert (d.current_air_time == 0).all()
    for k in range(1, 30):
        sim.step()
        scene.update(DT)
        torch.testing.assert_close(d.current_contact_time, torch.full((2, 1), (k + 1) * DT))
        assert not sensor.compute_first_contact(DT).any()
    for _ in range(100):
        sim.step()
        scene.update(DT)
    # at rest: the ground carries the weight (1 kg)
    torch.testing.assert_close(d.net_forces_w[..., 2], torch.full((2, 1), 9.81), atol=0.05, rtol=0)
    assert d.net_forces_w_history.shape == (2, 3, 1, 3)
    torch.testing.assert_close(d.net_forces_w_history[:, 0], d.net_forces_w)
    # lifted off the ground: the contact phase ends, its length is kept, the flight starts
    contact_time = d.current_contact_time.clone()
    box = scene["robot"]
    pose = box.data.root_state_w[:, :7].clone()
    pose[:, 2] += 0.5
    box.write_root_pose_to_sim(pose)
    box.write_root_velocity_to_sim(torch.zeros(2, 6))
    sim.step()
    scene.update(DT)
    assert sensor.compute_first_air(DT).all() and not sensor.compute_first_contact(DT).any()
    torch.testing.assert_close(d.last_contact_time, contact_time + DT)
    torch.testing.assert_close(d.current_air_time, torch.full((2, 1), DT))
    scene.reset(torch.tensor([True, False]))
    assert d.current_air_time[0] == 0 and d.current_air_time[1] > 0 and d.last_contact_time[0] == 0
    assert (d.net_forces_w_history[0] == 0).all() and (d.net_forces_w_history[1] != 0).any()


def test_contact_sensor_selects_bodies_by_regex_and_names_missing_ones():
    @configclass
    class SceneCfg(InteractiveSceneCfg):
        ground = AssetBaseCfg(prim_path="/World/ground", spawn=sim_utils.GroundPlaneCfg())
        robot = ANT_CFG.replace(prim_path="{ENV_REGEX_NS}/Robot")
        feet = ContactSensorCfg(prim_path="{ENV_REGEX_NS}/Robot/.*_foot", track_pose=True)

    sim, scene = make_scene(SceneCfg(num_envs=2, env_spacing=3.0))
    feet = scene["feet"]
    assert feet.body_names == ["front_left_foot", "front_right_foot", "left_back_foot", "right_back_foot"]
    assert feet.find_bodies("front_.*")[1] == ["front_left_foot", "front_right_foot"]
    scene.update(DT)
    assert feet.data.net_forces_w.shape == (2, 4, 3) and feet.data.pos_w.shape == (2, 4, 3)
    robot = scene["robot"]
    ids, _ = robot.find_bodies(".*_foot")
    torch.testing.assert_close(feet.data.pos_w, robot.data.body_pos_w[:, ids])
    for path, error in [
        ("{ENV_REGEX_NS}/Robot/.*_toe", r"matches no body of the model; bodies in the model: \['Robot/torso'"),
        ("{ENV_REGEX_NS}/Dog/.*", r"matches no body"),
    ]:
        sim_utils.SimulationContext.clear_instance()

        @configclass
        class BadCfg(SceneCfg):
            feet = ContactSensorCfg(prim_path=path)

        with pytest.raises(ValueError, match=error):
            make_scene(BadCfg(num_envs=1, env_spacing=3.0))
    sim_utils.SimulationContext.clear_instance()

    @configclass
    class FilteredCfg(SceneCfg):
        feet = ContactSensorCfg(prim_path="{ENV_REGEX_NS}/Robot/.*_foot", filter_prim_paths_expr=["/World/wall"])

    with pytest.raises(ValueError, match=r"filter_prim_paths_expr '/World/wall' matches no body and no static geom"):
        make_scene(FilteredCfg(num_envs=1, env_spacing=3.0))


def test_a_contact_sensor_over_several_objects_by_a_regex_of_their_names():
    """Isaac Lab's ``{ENV_REGEX_NS}/Obstacle.*`` selects every obstacle's body."""

    @configclass
    class SceneCfg(InteractiveSceneCfg):
        ground = AssetBaseCfg(prim_path="/World/ground", spawn=sim_utils.GroundPlaneCfg())
        obstacle_1 = box_cfg("{ENV_REGEX_NS}/Obstacle1", z=0.1)
        obstacle_2 = box_cfg("{ENV_REGEX_NS}/Obstacle2", z=0.1).replace(
            init_state=RigidObjectCfg.InitialStateCfg(pos=(0.5, 0.0, 0.1))
        )
        robot = box_cfg("{ENV_REGEX_NS}/Robot", z=0.1).replace(
            init_state=RigidObjectCfg.InitialStateCfg(pos=(-0.5, 0.0, 0.1))
        )
        contacts = ContactSensorCfg(prim_path="{ENV_REGEX_NS}/Obstacle.*")

    sim, scene = make_scene(SceneCfg(num_envs=2, env_spacing=3.0))
    sensor = scene["contacts"]
    assert sensor.num_bodies == 2  # the two obstacles, not the robot
    for _ in range(100):
        sim.step()
        scene.update(DT)
    weight = torch.full((2, 2), 9.81)  # each 1 kg box rests on the ground
    torch.testing.assert_close(sensor.data.net_forces_w[..., 2], weight, rtol=0.02, atol=0.0)
    sim_utils.SimulationContext.clear_instance()


def _engines():
    from test_engine_choice import _warp_on_cpu

    no_warp = pytest.mark.skipif(_warp_on_cpu() is not None, reason=str(_warp_on_cpu()))
    return [
        pytest.param("cpu", "auto", id="mujoco"),
        pytest.param("cpu", "mujoco_warp", marks=no_warp, id="mujoco_warp-cpu"),
        pytest.param("cuda:0", "auto", marks=[pytest.mark.gpu], id="cuda"),
    ]


@configclass
class StackSceneCfg(InteractiveSceneCfg):
    """A 2 kg box on the ground with a 1 kg box on it; a sensor on the lower box that tells the ground
    and the upper box apart."""

    ground = AssetBaseCfg(prim_path="/World/ground", spawn=sim_utils.GroundPlaneCfg())
    lower = box_cfg("{ENV_REGEX_NS}/Lower", z=0.1).replace(
        spawn=box_cfg("x", 0.0).spawn.replace(mass_props=sim_utils.MassPropertiesCfg(mass=2.0))
    )
    upper = box_cfg("{ENV_REGEX_NS}/Upper", z=0.3, size=0.15)
    contacts = ContactSensorCfg(
        prim_path="{ENV_REGEX_NS}/Lower",
        history_length=2,
        filter_prim_paths_expr=["/World/ground", "{ENV_REGEX_NS}/Upper"],
    )


@pytest.mark.parametrize(("device", "engine"), _engines())
def test_contact_force_matrix_separates_the_partners(device, engine):
    sim = sim_utils.SimulationContext(sim_utils.SimulationCfg(dt=DT, device=device, engine=engine))
    scene = InteractiveScene(StackSceneCfg(num_envs=2, env_spacing=3.0))
    sim.reset()
    sensor = scene["contacts"]
    assert sensor.filter_partner_names == ["ground", "Upper/body"]  # model names: static geoms, bodies
    push = torch.tensor([4.0, 0.0, 0.0], device=sim.device)  # below the friction limit: the stack stays
    for _ in range(300):
        scene["lower"].set_external_force_and_torque(push.expand(2, 1, 3), torch.zeros(2, 1, 3, device=sim.device))
        scene.write_data_to_sim()
        sim.step()
        scene.update(DT)
    d = sensor.data
    assert d.force_matrix_w.shape == (2, 1, 2, 3) and d.force_matrix_w_history.shape == (2, 2, 1, 2, 3)
    g = 9.81
    ground, upper = d.force_matrix_w[:, 0, 0], d.force_matrix_w[:, 0, 1]
    # the ground carries both boxes and holds the push by friction; the upper box presses down
    torch.testing.assert_close(ground, torch.tensor([[-4.0, 0.0, 3 * g]] * 2, device=sim.device), atol=0.05, rtol=0.01)
    torch.testing.assert_close(upper, torch.tensor([[0.0, 0.0, -g]] * 2, device=sim.device), atol=0.05, rtol=0.01)
    # the partners cover every contact: together they are the net force
    torch.testing.assert_close(ground + upper, d.net_forces_w[:, 0], atol=1e-3, rtol=1e-3)
    torch.testing.assert_close(d.force_matrix_w_history[:, 0], d.force_matrix_w)
    sensor.reset(torch.tensor([True, False], device=sim.device))
    assert bool((d.force_matrix_w[0] == 0).all()) and bool((d.force_matrix_w[1] != 0).any())


@configclass
class HangingSceneCfg(InteractiveSceneCfg):
    """A 1 kg box held in the air by an equality constraint (a ball joint to the world, as a closed loop's
    rod holds a leg) and one resting on the ground."""

    ground = AssetBaseCfg(prim_path="/World/ground", spawn=sim_utils.GroundPlaneCfg())
    hanging = box_cfg("{ENV_REGEX_NS}/Hanging", z=1.0)
    resting = box_cfg("{ENV_REGEX_NS}/Resting", z=0.1).replace(
        init_state=RigidObjectCfg.InitialStateCfg(pos=(1.0, 0.0, 0.1))
    )
    held = ContactSensorCfg(prim_path="{ENV_REGEX_NS}/Hanging")
    rests = ContactSensorCfg(prim_path="{ENV_REGEX_NS}/Resting")


@pytest.mark.parametrize(("device", "engine"), _engines())
def test_equality_constraint_forces_are_no_contact(device, engine):
    """Only contacts count (PhysX's contact report): the constraint holding the box up carries its weight,
    which MuJoCo's external body wrench (cfrc_ext) includes, but the box touches nothing."""
    import mujoco

    sim = sim_utils.SimulationContext(sim_utils.SimulationCfg(dt=DT, device=device, engine=engine))
    scene = InteractiveScene(HangingSceneCfg(num_envs=2, env_spacing=3.0))
    (hanging,) = [b.name for b in sim.spec.bodies if b.name.startswith("Hanging")]
    sim.spec.add_equality(
        type=mujoco.mjtEq.mjEQ_CONNECT, objtype=mujoco.mjtObj.mjOBJ_BODY, name1=hanging, data=[0, 0, 0.1] + [0] * 8
    )
    sim_utils.compute_body_interaction_forces(sim.spec)  # cfrc_ext too, to show what it would count
    sim.reset()
    for _ in range(100):
        sim.step()
        scene.update(DT)
    g = 9.81
    external = sim.physics.data("cfrc_ext")[:, sim.model.body(hanging).id, 3:6]
    torch.testing.assert_close(external[:, 2], torch.full((2,), g, device=sim.device), atol=0.05, rtol=0)
    assert bool((scene["held"].data.net_forces_w == 0).all())  # held in the air by the constraint alone
    rest = torch.tensor([[[0.0, 0.0, g]]] * 2, device=sim.device)
    torch.testing.assert_close(scene["rests"].data.net_forces_w, rest, atol=0.05, rtol=0)
    assert scene["hanging"].data.root_pos_w[:, 2].min() > 0.9  # it hangs, not fallen


@pytest.mark.parametrize(("device", "engine"), _engines())
def test_contact_points_are_where_the_boxes_touch(device, engine):
    @configclass
    class PointsSceneCfg(StackSceneCfg):
        contacts = ContactSensorCfg(
            prim_path="{ENV_REGEX_NS}/Lower",
            filter_prim_paths_expr=["/World/ground", "{ENV_REGEX_NS}/Upper"],
            track_contact_points=True,
        )

    sim = sim_utils.SimulationContext(sim_utils.SimulationCfg(dt=DT, device=device, engine=engine))
    scene = InteractiveScene(PointsSceneCfg(num_envs=2, env_spacing=3.0))
    sim.reset()
    for _ in range(100):
        sim.step()
        scene.update(DT)
    points = scene["contacts"].data.contact_pos_w  # (N, B=1, M=2, 3): the lower box on the ground, under the upper
    assert points.shape == (2, 1, 2, 3)
    origins = scene.env_origins[:, :2]
    torch.testing.assert_close(points[:, 0, 0, :2], origins, atol=1e-3, rtol=0)  # the middle of its bottom face
    torch.testing.assert_close(points[:, 0, 0, 2], torch.zeros(2, device=sim.device), atol=2e-3, rtol=0)
    torch.testing.assert_close(points[:, 0, 1, 2], torch.full((2,), 0.2, device=sim.device), atol=2e-3, rtol=0)
    scene["upper"].write_root_pose_to_sim(  # lift the upper box away: no contact, no point
        torch.tensor([[0.0, 0.0, 2.0, 1.0, 0.0, 0.0, 0.0]], device=sim.device).repeat(2, 1)
        + torch.cat([scene.env_origins, torch.zeros(2, 4, device=sim.device)], dim=1)
    )
    sim.step()
    scene.update(DT)
    assert torch.isnan(points[:, 0, 1]).all() and not torch.isnan(points[:, 0, 0]).any()
    scene["contacts"].reset(torch.tensor([True, False], device=sim.device))
    assert torch.isnan(points[0]).all() and not torch.isnan(points[1, 0, 0]).any()
    sim_utils.SimulationContext.clear_instance()


def test_contact_points_need_partners():
    with pytest.raises(ConfigError, match=r"track_contact_points=True needs filter_prim_paths_expr"):
        make_scene(StackSceneCfg(num_envs=1, env_spacing=3.0).replace(
            contacts=ContactSensorCfg(prim_path="{ENV_REGEX_NS}/Lower", track_contact_points=True)))  # fmt: skip


def test_contact_sensor_bodies_in_the_articulations_order():
    """A sensor over all of a robot's bodies lists them as the robot does (level by level)."""
    from simlab.robots.unitree import UNITREE_GO2_CFG

    @configclass
    class SceneCfg(InteractiveSceneCfg):
        ground = AssetBaseCfg(prim_path="/World/ground", spawn=sim_utils.GroundPlaneCfg())
        robot = UNITREE_GO2_CFG.replace(prim_path="{ENV_REGEX_NS}/Robot")
        contacts = ContactSensorCfg(prim_path="{ENV_REGEX_NS}/Robot/.*")
        feet = ContactSensorCfg(
            prim_path="{ENV_REGEX_NS}/Robot/.*_foot",
            filter_prim_paths_expr=["/World/ground", "{ENV_REGEX_NS}/Robot/base"],
        )

    sim, scene = make_scene(SceneCfg(num_envs=1, env_spacing=3.0))
    robot, contacts, feet = scene["robot"], scene["contacts"], scene["feet"]
    assert contacts.body_names == robot.body_names
    assert contacts.body_names[:5] == ["base", "FL_hip", "FR_hip", "RL_hip", "RR_hip"]
    assert feet.filter_partner_names == ["ground", "Robot/base"]
    for _ in range(100):
        scene.write_data_to_sim()
        sim.step()
        scene.update(DT)
    # the feet stand on the ground and never touch the base; the name lookups agree with the data
    ids, _ = feet.find_bodies(".*_foot")
    torch.testing.assert_close(feet.data.force_matrix_w[:, :, 0], feet.data.net_forces_w[:, ids], atol=1e-3, rtol=1e-3)
    assert float(feet.data.force_matrix_w[..., 0, 2].min()) > 5.0
    assert bool((feet.data.force_matrix_w[:, :, 1] == 0).all())


def test_contact_sensor_adds_no_mujoco_sensor_for_a_body_that_cannot_touch(monkeypatch):
    """Only bodies with a colliding geom get a MuJoCo contact sensor (each costs MuJoCo Warp a pass over
    the contacts); the G1's 12 bodies without one (hip pitch and roll links, ankle pitch links, ...) read
    zero. The forces are those of a sensor on every body: the same G1, dropped on its side so that legs,
    arms and fingers touch, gives bit-equal readings with a MuJoCo sensor added for every body (the earlier build)."""
    import mujoco

    import simlab.sensors.contact_sensor as contact_sensor
    from simlab.robots.unitree import G1_CFG

    @configclass
    class SceneCfg(InteractiveSceneCfg):
        ground = AssetBaseCfg(prim_path="/World/ground", spawn=sim_utils.GroundPlaneCfg())
        robot = G1_CFG.replace(prim_path="{ENV_REGEX_NS}/Robot")
        contacts = ContactSensorCfg(prim_path="{ENV_REGEX_NS}/Robot/.*")

    def run() -> tuple[torch.Tensor, int, list[str]]:
        sim_utils.SimulationContext.clear_instance()
        sim, scene = make_scene(SceneCfg(num_envs=1, env_spacing=3.0))
        robot = scene["robot"]
        on_side = torch.tensor([[0.0, 0.0, 0.3, math.cos(math.pi / 4), math.sin(math.pi / 4), 0.0, 0.0]])
        robot.write_root_pose_to_sim(on_side)
        for _ in range(100):
            scene.write_data_to_sim()
            sim.step()
            scene.update(DT)
        model = sim.model
        sensors = sum(int(t) == mujoco.mjtSensor.mjSENS_CONTACT for t in model.sensor_type)
        return scene["contacts"].data.net_forces_w.clone(), sensors, scene["contacts"].body_names

    forces, sensors, names = run()
    # the bodies without a colliding geom in the G1's model (no collision shape on them)
    idle = [i for i, name in enumerate(names) if not name.endswith(TOUCHING_G1_BODIES)]
    assert len(names) == 38 and sensors == 26 and len(idle) == 12
    assert bool((forces[:, idle] == 0).all())
    touching = [i for i in range(38) if i not in idle and float(forces[0, i].norm()) > 1.0]
    assert len(touching) >= 3, [names[i] for i in touching]  # a thigh, an arm and a foot lie on the ground
    monkeypatch.setattr(contact_sensor, "_bodies_that_can_touch", lambda spec: {b.name for b in spec.bodies})
    every_body, sensors_every_body, _ = run()
    assert sensors_every_body == 38
    assert torch.equal(forces, every_body)


TOUCHING_G1_BODIES = (
    "pelvis", "hip_yaw_link", "knee_link", "ankle_roll_link", "torso_link", "shoulder_yaw_link", "elbow_pitch_link",
    "elbow_roll_link", "one_link", "two_link", "three_link", "four_link", "five_link", "six_link",
)  # fmt: skip


# -- in an env step ---------------------------------------------------------------------------------


def scan_obs(env, sensor_cfg, offset: float = 0.5):
    """Isaac Lab's height_scan observation, as written there."""
    sensor = env.scene.sensors[sensor_cfg.name]
    return sensor.data.pos_w[:, 2].unsqueeze(1) - sensor.data.ray_hits_w[..., 2] - offset


@pytest.mark.parametrize("device", DEVICES)
def test_height_scan_in_env_steps_follows_resets(device):
    """A manager-based env on a generated terrain with the height scanner of Isaac Lab's rough
    tasks (update_period = decimation * dt): the observation a step returns is the scan at the
    robot's pose then, also for envs just reset to a new place (the scan is cast after the reset)."""

    @configclass
    class SceneCfg(InteractiveSceneCfg):
        terrain = TerrainImporterCfg(
            prim_path="/World/ground", terrain_type="generator", terrain_generator=small_terrain()
        )
        robot = ANT_CFG.replace(prim_path="{ENV_REGEX_NS}/Robot")
        height_scanner = scanner_cfg(prim_path="{ENV_REGEX_NS}/Robot/torso")
        contact_forces = ContactSensorCfg(prim_path="{ENV_REGEX_NS}/Robot/.*", history_length=3, track_air_time=True)

    @configclass
    class ObservationsCfg:
        @configclass
        class PolicyCfg(ObsGroup):
            height_scan = ObsTerm(func=scan_obs, params={"sensor_cfg": SceneEntityCfg("height_scanner")})

        policy: PolicyCfg = PolicyCfg()

    @configclass
    class EventsCfg:
        reset_base = EventTermCfg(
            func=mdp.reset_root_state_uniform,
            mode="reset",
            params={"pose_range": {"x": (-0.5, 0.5), "y": (-0.5, 0.5), "yaw": (-3.14, 3.14)}, "velocity_range": {}},
        )

    @configclass
    class ActionsCfg:
        joints = mdp.JointEffortActionCfg(asset_name="robot", joint_names=[".*"], scale=5.0)

    @configclass
    class RewardsCfg:
        alive = RewTerm(func=mdp.is_alive, weight=1.0)

    @configclass
    class TerminationsCfg:
        time_out = DoneTerm(func=mdp.time_out, time_out=True)

    @configclass
    class EnvCfg(ManagerBasedRLEnvCfg):
        scene = SceneCfg(num_envs=4, env_spacing=2.0)
        observations = ObservationsCfg()
        actions = ActionsCfg()
        rewards = RewardsCfg()
        terminations = TerminationsCfg()
        events = EventsCfg()

        def __post_init__(self):
            self.decimation = 4
            self.episode_length_s = 6 * 4 * 0.005  # every env ends at step 6
            self.sim.dt = 0.005
            self.sim.device = device
            self.seed = 0
            self.scene.height_scanner.update_period = self.decimation * self.sim.dt

    cfg = EnvCfg()
    env = ManagerBasedRLEnv(cfg)
    try:
        env.reset()
        sensor, robot = env.scene["height_scanner"], env.scene["robot"]
        for step in range(1, 9):
            obs, _, _, truncated, extras = env.step(torch.zeros(4, 8, device=env.device))
            scan = obs["policy"]
            assert scan.shape == (4, 187) and torch.isfinite(scan).all()
            # the scan was cast at the robot's pose now (after this step's resets)
            torch.testing.assert_close(sensor.data.pos_w, robot.data.root_pos_w, atol=1e-4, rtol=0)
            torch.testing.assert_close(scan, scan_obs(env, SceneEntityCfg("height_scanner")), atol=1e-5, rtol=0)
            if step == 6:
                assert truncated.all()
                before = extras["final_obs"]["policy"]
                assert not torch.allclose(before, scan)  # each env scans the ground of its new place
    finally:
        env.close()


def test_binned_ray_casts_agree_with_casts_against_every_geom():
    """The CPU caster casts vertical rays against the targets of their xy bin only: the distances
    equal mj_ray's against every target geom, for vertical and oblique rays, inside and outside
    the terrain."""
    from simlab.sensors.ray_caster.ray_targets import _mjbatch_rays, _MujocoCaster, find_target_geoms, target_model

    @configclass
    class SceneCfg(InteractiveSceneCfg):
        terrain = TerrainImporterCfg(
            prim_path="/World/ground", terrain_type="generator", terrain_generator=small_terrain(box_tiles_as="boxes")
        )

    sim, _ = make_scene(SceneCfg(num_envs=1, env_spacing=2.0))
    model = target_model(sim.model, find_target_geoms(sim.model, ["/World/ground"], "test"))
    n = 4000
    g = torch.Generator().manual_seed(0)
    starts = (torch.rand(n, 3, generator=g) - 0.5) * torch.tensor([12.0, 26.0, 2.0]) + torch.tensor([0.0, 0.0, 2.0])
    directions = torch.zeros(n, 3)
    directions[:, 2] = -1.0
    oblique = torch.rand(n, generator=g) < 0.25
    directions[oblique] = torch.nn.functional.normalize(torch.randn(int(oblique.sum()), 3, generator=g), dim=-1)
    caster = _MujocoCaster(model, n, num_threads=2)
    assert len(caster.bins) > 1
    binned = caster.cast(starts, directions)
    every_geom = _mjbatch_rays(caster.full, starts, directions)
    assert (binned >= 0).sum() > n / 2
    torch.testing.assert_close(binned, every_geom, atol=1e-5, rtol=0)


def test_ray_caster_debug_vis_draws_the_hits():
    """``RayCasterCfg(debug_vis=True)``: a red marker at every hit of the rendered env, misses not drawn."""
    import numpy as np

    from simlab.sim.renderer import OffscreenRenderer

    cfg = PlaneSceneCfg(num_envs=2, env_spacing=4.0)
    cfg.height_scanner = scanner_cfg(debug_vis=True)
    sim, scene = make_scene(cfg)
    sensor = scene["height_scanner"]
    place(
        sim, scene, "robot", scene.env_origins.cpu() + torch.tensor([0.0, 0.0, 2.0]), torch.tensor([[1.0, 0, 0, 0]] * 2)
    )
    try:
        renderer = OffscreenRenderer(sim.model, 160, 120, 1)
    except RuntimeError as err:  # no OpenGL on this machine
        pytest.skip(f"offscreen rendering unavailable: {err}")
    eye, lookat = (2.5, 0.0, 2.5), (0.0, 0.0, PLANE_HEIGHT)
    marked = renderer.render(sim.physics, [0], np.zeros((1, 3)), eye, lookat).astype(np.int32)
    assert sensor.ray_visualizer.count == 2 * 187  # every ray hits the plane
    sensor.set_debug_vis(False)
    plain = renderer.render(sim.physics, [0], np.zeros((1, 3)), eye, lookat).astype(np.int32)
    renderer.close()
    changed = np.abs(marked - plain).sum(-1) > 30
    assert changed.sum() > 100
    red = marked[changed]
    assert (red[:, 0] > red[:, 1] + 60).mean() > 0.8  # RAY_CASTER_MARKER_CFG's red spheres
    # the live viewers get the followed env's markers with each snapshot (drawn in their own thread)
    import mujoco

    from simlab.sim.renderer import draw_decor
    from simlab.viewer.source import SimSource

    sensor.set_debug_vis(True)
    snapshot = SimSource.of_sim(sim).snapshot([1], np.zeros((1, 3)))
    assert len(snapshot.decor) == 187
    local_hits = (sensor.data.ray_hits_w[1] - scene.env_origins[1]).numpy()
    drawn = np.array([pos for _, _, pos, _, _ in snapshot.decor])
    np.testing.assert_allclose(np.sort(drawn, axis=0), np.sort(local_hits, axis=0), atol=1e-5)
    viewer_scene = mujoco.MjvScene(sim.model, maxgeom=500)
    draw_decor(viewer_scene, snapshot.decor)
    assert viewer_scene.ngeom == 187
    # a hit at inf (a miss) is not drawn
    sensor.data.ray_hits_w[0, :10] = torch.inf
    sim.run_render_callbacks()
    assert sensor.ray_visualizer.count == 2 * 187 - 10


def test_contact_sensor_debug_vis_marks_each_body_red_in_contact():
    """``ContactSensorCfg(debug_vis=True)``: a sphere at each sensor body, Isaac Lab's marker 0 ("contact")
    while its net force exceeds force_threshold, marker 1 ("no_contact") in the air."""
    cfg = DropSceneCfg(num_envs=2, env_spacing=3.0)
    cfg.contacts = cfg.contacts.replace(debug_vis=True)
    sim, scene = make_scene(cfg)
    sensor = scene["contacts"]
    markers = sensor.contact_visualizer
    sim.step()
    scene.update(DT)
    sim.run_render_callbacks()  # in the air
    assert markers.count == 2 and markers._indices.tolist() == [1, 1]
    torch.testing.assert_close(torch.as_tensor(markers._translations).float(), scene["robot"].data.root_pos_w)
    for _ in range(150):  # lands and comes to rest
        sim.step()
        scene.update(DT)
    sim.run_render_callbacks()
    assert markers._indices.tolist() == [0, 0]
    sensor.set_debug_vis(False)
    assert not markers.is_visible()


def test_sensor_on_assets_under_create_prim_groups():
    """Isaac Lab's ray-caster tutorial: balls at ``/World/Origin.*/ball`` under four ``create_prim``
    groups (one world each) carry a ray caster with the same prim path; each scans from its own ball."""
    import simlab.sim.utils as prim_utils
    from simlab.assets import RigidObject
    from simlab.sensors import RayCaster

    sim = sim_utils.SimulationContext(sim_utils.SimulationCfg(dt=DT, device="cpu"))
    ground = sim_utils.GroundPlaneCfg()
    ground.func("/World/ground", ground)
    origins = [[0.25, 0.25, 0.0], [-0.25, 0.25, 0.0], [0.25, -0.25, 0.0], [-0.25, -0.25, 0.0]]
    for i, origin in enumerate(origins):
        prim_utils.create_prim(f"/World/Origin{i}", "Xform", translation=origin)
    balls = RigidObject(box_cfg("/World/Origin.*/ball", z=1.0))
    scanner = RayCaster(scanner_cfg(prim_path="/World/Origin.*/ball", debug_vis=False))
    sim.reset()
    balls.update(DT)
    scanner.update(DT, force_recompute=True)
    # pos_w is the ball's (Isaac Lab folds the 20 m offset into the ray starts); every ray hits the ground
    torch.testing.assert_close(scanner.data.pos_w, torch.tensor(origins) + torch.tensor([0.0, 0.0, 1.0]))
    hits = scanner.data.ray_hits_w
    assert hits.shape == (4, 187, 3)
    torch.testing.assert_close(hits[..., 2], torch.zeros(4, 187), atol=1e-4, rtol=0)
    torch.testing.assert_close(hits[..., :2].mean(1), torch.tensor(origins)[:, :2], atol=1e-4, rtol=0)
