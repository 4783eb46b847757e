"""Per-env scale and color of an asset ('prestartup' events): per-world model fields the physics uses."""

from __future__ import annotations

import pytest
import torch

import simlab.envs.mdp as mdp
import simlab.sim as sim_utils
from simlab.assets import RigidObjectCfg
from simlab.envs import ManagerBasedEnv, ManagerBasedEnvCfg
from simlab.managers import EventTermCfg as EventTerm
from simlab.managers import ObservationGroupCfg as ObsGroup
from simlab.managers import ObservationTermCfg as ObsTerm
from simlab.managers import SceneEntityCfg
from simlab.scene import InteractiveSceneCfg
from simlab.terrains import TerrainImporterCfg
from simlab.utils import configclass

CUBE = SceneEntityCfg("cube")


@configclass
class CubeSceneCfg(InteractiveSceneCfg):
    terrain = TerrainImporterCfg(prim_path="/World/ground", terrain_type="plane")
    cube = RigidObjectCfg(
        prim_path="{ENV_REGEX_NS}/cube",
        spawn=sim_utils.CuboidCfg(
            size=(0.2, 0.2, 0.2),
            rigid_props=sim_utils.RigidBodyPropertiesCfg(),
            mass_props=sim_utils.MassPropertiesCfg(mass=1.0),
            collision_props=sim_utils.CollisionPropertiesCfg(),
        ),
        init_state=RigidObjectCfg.InitialStateCfg(pos=(0.0, 0.0, 0.5)),
    )


@configclass
class ObservationsCfg:
    @configclass
    class PolicyCfg(ObsGroup):
        height = ObsTerm(func=mdp.root_pos_w, params={"asset_cfg": CUBE})

    policy: PolicyCfg = PolicyCfg()


@configclass
class EventCfg:
    scale = EventTerm(
        func=mdp.randomize_rigid_body_scale,
        mode="prestartup",
        params={"scale_range": {"x": (0.5, 1.5), "y": (0.5, 1.5), "z": (0.5, 1.5)}, "asset_cfg": CUBE},
    )
    color = EventTerm(
        func=mdp.randomize_visual_color,
        mode="prestartup",
        params={"colors": [(1.0, 0.0, 0.0), (0.0, 0.0, 1.0)], "asset_cfg": CUBE, "mesh_name": "geometry/mesh"},
    )


@configclass
class ActionsCfg:
    pass


@configclass
class CubeEnvCfg(ManagerBasedEnvCfg):
    scene = CubeSceneCfg(num_envs=6, env_spacing=2.0, replicate_physics=False)
    observations = ObservationsCfg()
    actions = ActionsCfg()
    events = EventCfg()

    def __post_init__(self):
        self.decimation = 5
        self.sim.dt = 0.004
        self.sim.device = "cpu"


@pytest.mark.parametrize("engine", ["mujoco", "mujoco_warp"])  # MuJoCo Warp on the CPU runs the GPU backend
def test_scaled_cubes_come_to_rest_on_their_own_half_height(engine):
    if engine == "mujoco_warp":
        pytest.importorskip("mujoco_warp")
    cfg = CubeEnvCfg()
    cfg.sim.engine = engine
    env = ManagerBasedEnv(cfg)
    try:
        env.reset()
        physics = env.sim.physics
        cube = env.scene["cube"]
        geom = int(torch.nonzero(torch.as_tensor(env.sim.model.geom_bodyid) == cube._body_ids[0])[0])
        half = physics.model_field("geom_size")[:, geom].clone()  # (num_envs, 3) half sizes
        scale = half / 0.1
        assert ((scale >= 0.5) & (scale <= 1.5)).all() and scale[:, 2].std() > 0.05  # each env its own
        rgb = physics.model_field("geom_rgba")[:, geom, :3]
        assert all(row.tolist() in ([1.0, 0.0, 0.0], [0.0, 0.0, 1.0]) for row in rgb)
        for _ in range(60):  # 1.2 s: dropped from 0.5 m, each cube lands on its own face
            env.step(torch.zeros(env.num_envs, 0))
        rest_height = cube.data.root_pos_w[:, 2]
        assert torch.allclose(rest_height, half[:, 2], atol=5e-3), (rest_height, half[:, 2])
    finally:
        env.close()


def test_renders_draw_each_env_with_its_own_color_and_size():
    from simlab.sim.renderer import OffscreenRenderer

    env = ManagerBasedEnv(CubeEnvCfg())
    try:
        env.reset()
        for _ in range(60):  # the cubes come to rest
            env.step(torch.zeros(env.num_envs, 0))
        physics = env.sim.physics
        geom = int(torch.nonzero(torch.as_tensor(env.sim.model.geom_bodyid) == env.scene["cube"]._body_ids[0])[0])
        rgb = physics.model_field("geom_rgba")[:, geom, :3]
        volume = physics.model_field("geom_size")[:, geom].prod(dim=-1)
        renderer = OffscreenRenderer(env.sim.model, 96, 96, max_envs=1)
        pixels = []
        for env_id in range(env.num_envs):  # each env alone, seen from the same place over its cube
            cube = (env.scene["cube"].data.root_pos_w[env_id] - env.scene.env_origins[env_id]).numpy()  # env frame
            image = renderer.render(physics, [env_id], [[0.0, 0.0, 0.0]], eye=cube + [0.0, -0.8, 0.8], lookat=cube)
            red, blue = image[..., 0].astype(int), image[..., 2].astype(int)
            own, other = (red, blue) if rgb[env_id, 0] > 0.5 else (blue, red)
            drawn = own > other + 40  # the cube's pixels, in its own color
            assert drawn.sum() > 50 and (other > own + 40).sum() == 0, env_id
            pixels.append(int(drawn.sum()))
        renderer.close()
        order = torch.argsort(volume)
        assert pixels[int(order[-1])] > pixels[int(order[0])]  # the largest cube covers more of the image
    finally:
        env.close()
