"""What a height scan costs per env step (the pose it needs, the geoms each ray is tested against), the
rough G1 step's launches, and the rough humanoids' contact buffers on the terrain they scan (issue 39)."""

from __future__ import annotations

import numpy as np
import pytest
import torch

import simlab.sim as sim_utils
from simlab.assets import AssetBaseCfg
from simlab.robots.unitree import UNITREE_GO2_CFG
from simlab.scene import InteractiveScene, InteractiveSceneCfg
from simlab.sensors import RayCasterCfg, patterns
from simlab.utils import configclass


def _stale_go2_scene_counting_forwards(scene_cfg_class: type, sensor: str) -> tuple:
    """Two Go2 worlds of ``scene_cfg_class`` on MuJoCo Warp (Warp's CPU device), stepped three times with
    their legs driven, their derived state stale; the list that ``physics.forward`` appends to from now
    on: (sim, robot, the scene's ``sensor``, forwards)."""
    sim = sim_utils.SimulationContext(sim_utils.SimulationCfg(dt=0.005, device="cpu", engine="mujoco_warp"))
    scene = InteractiveScene(scene_cfg_class(num_envs=2, env_spacing=2.0))
    sim.reset()
    physics, robot = sim.physics, scene["robot"]
    forwards = []
    original = physics.forward
    physics.forward = lambda *args, **kwargs: forwards.append(1) or original(*args, **kwargs)
    for _ in range(3):
        robot.set_joint_position_target(robot.data.default_joint_pos + 0.2)
        scene.write_data_to_sim()
        sim.step()
        scene.update(sim.get_physics_dt())
    assert physics.is_stale
    forwards.clear()
    return sim, robot, scene[sensor], forwards


def test_height_scanner_on_a_child_body_needs_the_kinematics_not_a_forward():
    """A scanner on a body below the floating base (the G1's torso_link) reads its pose from the
    kinematics pass: on MuJoCo Warp a forward is the collision and a constraint solve (262 launches for
    the rough G1, a fifth physics step per env step), the kinematics 22. Same hits as after a forward."""

    @configclass
    class SceneCfg(InteractiveSceneCfg):
        ground = AssetBaseCfg(prim_path="/World/ground", spawn=sim_utils.GroundPlaneCfg())
        robot = UNITREE_GO2_CFG.replace(prim_path="{ENV_REGEX_NS}/Robot")
        scanner = RayCasterCfg(
            prim_path="{ENV_REGEX_NS}/Robot/FL_thigh",
            offset=RayCasterCfg.OffsetCfg(pos=(0.0, 0.0, 20.0)),
            ray_alignment="yaw",
            pattern_cfg=patterns.GridPatternCfg(resolution=0.5, size=[1.0, 1.0]),
            mesh_prim_paths=["/World/ground"],
        )

    sim, robot, scanner, forwards = _stale_go2_scene_counting_forwards(SceneCfg, "scanner")
    pos, hits = scanner.data.pos_w.clone(), scanner.data.ray_hits_w.clone()
    assert forwards == [], "the scan ran a forward"
    sim.forward()
    scanner.update(0.0, force_recompute=True)
    torch.testing.assert_close(pos, robot.data.body_pos_w[:, robot.find_bodies("FL_thigh")[0][0]])
    torch.testing.assert_close(scanner.data.ray_hits_w, hits)


@pytest.mark.parametrize("robot", ["G1", "H1"])
def test_rough_humanoid_contact_buffers_hold_the_robot_fallen_on_the_hardest_terrains(robot):
    """The rough G1 and H1 reserve MuJoCo Warp buffers from measured peaks (``sim.mujoco.nconmax`` /
    ``njmax`` per world; MuJoCo Warp's estimate reserved 256 contacts and 2122 rows for the G1, 192 and
    1574 for the H1, which its constraint kernels and memory pay for in every world). The worst case is
    the robot lying on the terrain: 16 worlds drop it 0.3 m onto its front, back or sides at random
    points of the hardest row's tiles (stairs up and down, boxes, roughness, slopes), three in four
    driven to random points of their joint ranges, for 1.5 s on MuJoCo Warp (Warp's CPU device). The
    reserved sizes hold 1.5 times the peaks and nothing overflows. Peaks of such runs over 320 worlds:
    G1 41 contacts, 166 rows; H1 33 and 132 (MuJoCo C's own height-field collision gives more, for the
    G1 52 and 213 in 24 worlds, but MuJoCo C grows its buffers)."""
    import gymnasium as gym
    import mujoco

    import simlab.tasks  # noqa: F401 - registers the tasks
    from simlab.sensors.ray_caster.ray_targets import find_target_geoms, target_model
    from simlab.sim.backends.buffer_peaks import BufferPeaks
    from simlab.tasks.utils.parse_cfg import parse_env_cfg

    task, worlds = f"simlab/Velocity-Rough-{robot}-v0", 16
    cfg = parse_env_cfg(task, device="cpu", num_envs=worlds)
    reserved = (cfg.sim.mujoco.nconmax, cfg.sim.mujoco.njmax)
    cfg.sim.engine, cfg.sim.use_cuda_graph, cfg.seed = "mujoco_warp", False, 0
    cfg.sim.mujoco.nconmax, cfg.sim.mujoco.njmax = 4 * reserved[0], 4 * reserved[1]  # room to measure
    env = gym.make(task, cfg=cfg).unwrapped
    try:
        env.reset()
        robot, physics, model = env.scene["robot"], env.sim.physics, env.sim.model
        assert float(env.sim.env_origins.abs().max()) == 0.0, "the worlds share the terrain's frame"
        terrain = target_model(model, find_target_geoms(model, ["/World/ground"], "test"))
        terrain_data = mujoco.MjData(terrain)
        mujoco.mj_kinematics(terrain, terrain_data)
        generator = torch.Generator().manual_seed(1)
        tiles = env.scene.terrain.terrain_origins[-1]  # the hardest row: one tile per column
        position = torch.zeros(worlds, 3)
        for world in range(worlds):
            angle, radius = 2 * torch.pi * torch.rand(2, generator=generator) * torch.tensor([1.0, 0.35])
            xy = tiles[(world * 7) % len(tiles), :2] + (0.8 + radius) * torch.stack((angle.cos(), angle.sin()))
            start, down = np.array([*xy.tolist(), 50.0]), np.array([0.0, 0.0, -1.0])
            down = mujoco.mj_ray(terrain, terrain_data, start, down, None, 1, -1, np.zeros(1, np.int32))
            position[world] = torch.tensor([*xy.tolist(), 50.0 - down + 0.3])
        low, high = robot.data.joint_pos_limits.unbind(-1)
        default = robot.data.default_joint_pos
        targets = low + torch.rand(low.shape, generator=generator) * (high - low)
        targets[::4] = default[::4]
        # lying: a quarter turn about +y (on the front), -y (back), +x and -x (sides)
        axes = torch.tensor([[0.0, 1.0, 0.0], [0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [-1.0, 0.0, 0.0]]).repeat(4, 1)
        half = torch.tensor(torch.pi / 4)
        quat = torch.cat((torch.cos(half).expand(worlds, 1), torch.sin(half) * axes), dim=-1)
        robot.write_root_pose_to_sim(torch.cat((position, quat), dim=-1))
        robot.write_root_velocity_to_sim(torch.zeros(worlds, 6))
        robot.write_joint_state_to_sim(default, torch.zeros_like(default))
        peaks = BufferPeaks().watch(physics)
        for _ in range(round(1.5 / env.physics_dt)):
            robot.set_joint_position_target(targets)
            env.scene.write_data_to_sim()
            env.sim.step(render=False)
        peaks.unwatch()
        physics.check_overflow()
        assert peaks.contacts_per_world >= 15, f"the robots lie on the terrain: {peaks}"
        assert reserved[0] >= 1.5 * peaks.contacts_per_world, f"{peaks}, nconmax {reserved[0]}"
        assert reserved[1] >= 1.5 * peaks.constraint_rows, f"{peaks}, njmax {reserved[1]}"
    finally:
        env.close()


def test_binned_warp_rays_equal_mujoco_warps_cast_against_every_geom():
    """On MuJoCo Warp a vertical ray is tested against its xy bin's geoms alone (one height-field tile
    of the rough terrain instead of all 204 targets): bit for bit the distances and normals of
    ``mujoco_warp.rays`` against every geom, for rays inside tiles, on the tiles' shared edges (tested
    against all), off the terrain (a miss) and slanted (tested against all)."""
    from simlab.sensors.ray_caster.ray_targets import XyBins, _WarpCaster, find_target_geoms, target_model
    from simlab.terrains import ROUGH_TERRAINS_CFG, TerrainImporterCfg

    @configclass
    class SceneCfg(InteractiveSceneCfg):
        terrain = TerrainImporterCfg(
            prim_path="/World/ground",
            terrain_type="generator",
            terrain_generator=ROUGH_TERRAINS_CFG.replace(seed=0, num_rows=4, num_cols=6),
        )

    sim = sim_utils.SimulationContext(sim_utils.SimulationCfg(dt=0.005, device="cpu", engine="mujoco_warp"))
    InteractiveScene(SceneCfg(num_envs=1, env_spacing=2.0))
    sim.reset()
    model = target_model(sim.model, find_target_geoms(sim.model, ["/World/ground"], "test"))
    bins = XyBins(model)
    assert not bins.empty and max(len(ids) for ids in bins.geoms) <= 2, "a tile per bin (and a border box)"
    generator = torch.Generator().manual_seed(0)
    n = 3000
    low = torch.tensor(bins.origin) - 3.0
    span = torch.tensor(bins.counts) * bins.size + 6.0
    xy = low + torch.rand(n, 2, generator=generator, dtype=torch.float64) * span
    edges = torch.randint(0, int(bins.counts[0]) + 1, (500,), generator=generator)
    xy[:500, 0] = bins.origin[0] + bins.size * edges  # on the cells' edges
    starts = torch.cat((xy.float(), torch.full((n, 1), 10.0)), dim=1)
    directions = torch.tensor([0.0, 0.0, -1.0]).repeat(n, 1)
    directions[-200:] = torch.nn.functional.normalize(torch.tensor([0.3, -0.2, -1.0]), dim=0)
    binned = _WarpCaster(model, n, sim.physics, "cpu")
    every_geom = _WarpCaster(model, n, sim.physics, "cpu", binned=False)
    distance, normal = (t.clone() for t in binned.cast(starts, directions, with_normals=True))
    expected_distance, expected_normal = every_geom.cast(starts, directions, with_normals=True)
    assert (expected_distance >= 0).sum() > 2000 and (expected_distance < 0).any(), "hits and misses"
    assert torch.equal(distance, expected_distance)
    assert torch.equal(normal, expected_normal)


def test_rough_g1_step_launches_no_forward_outside_the_physics():
    """The rough G1 env step on the GPU backend (Warp's CPU device, ``simlab bench ops step``): outside
    the physics only the kinematics pass launches Warp kernels (22 per pass, before and after the
    resets); 285 when the height scan ran a forward (262)."""
    from simlab.benchmarks import step_ops

    counter = step_ops.count("simlab/Velocity-Rough-G1-v0", num_envs=2, steps=1)
    report = step_ops.report(counter, 1)
    outside = sum(n for label, n in counter.warp_launches.items() if label != "physics")
    assert not any("forward" in label for label in counter.warp_launches), report
    assert outside <= 45, f"{outside} Warp launches per step outside the physics:\n{report}"


def test_ray_caster_camera_on_a_body_needs_the_kinematics_not_a_forward():
    """As the height scanner: a ray-caster camera riding on a robot's body reads the body's pose from the
    kinematics pass on MuJoCo Warp, not a forward; the same image as after a forward."""
    from simlab.sensors import RayCasterCameraCfg

    @configclass
    class SceneCfg(InteractiveSceneCfg):
        ground = AssetBaseCfg(prim_path="/World/ground", spawn=sim_utils.GroundPlaneCfg())
        robot = UNITREE_GO2_CFG.replace(prim_path="{ENV_REGEX_NS}/Robot")
        camera = RayCasterCameraCfg(
            prim_path="{ENV_REGEX_NS}/Robot/FL_thigh",
            mesh_prim_paths=["/World/ground"],
            offset=RayCasterCameraCfg.OffsetCfg(pos=(0.0, 0.0, 1.0), rot=(0.0, 1.0, 0.0, 0.0)),
            data_types=["distance_to_image_plane"],
            pattern_cfg=patterns.PinholeCameraPatternCfg(width=8, height=6),
        )

    sim, robot, camera, forwards = _stale_go2_scene_counting_forwards(SceneCfg, "camera")
    depth = camera.data.output["distance_to_image_plane"].clone()
    assert forwards == [], "the camera ran a forward"
    assert torch.isfinite(depth).all() and (depth > 0.5).all(), "the ground seen from above the thigh"
    sim.forward()
    camera.update(0.0, force_recompute=True)
    torch.testing.assert_close(camera.data.output["distance_to_image_plane"], depth)
