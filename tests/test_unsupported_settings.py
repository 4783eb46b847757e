"""Settings simlab cannot honour are refused with a reason; the ones it keeps do what they say.

Each refused setting still loads with its default value (Isaac Lab configs that leave it alone work).
"""

from __future__ import annotations

import numpy as np
import pytest
import torch
from conftest import DEVICES, rendering_available

import simlab.envs.mdp as mdp
import simlab.sim as sim_utils
from simlab.actuators import DCMotorCfg, IdealPDActuatorCfg, ImplicitActuatorCfg
from simlab.assets import AssetBaseCfg
from simlab.envs import ManagerBasedRLEnv
from simlab.robots.cartpole import CARTPOLE_CFG
from simlab.scene import InteractiveScene, InteractiveSceneCfg
from simlab.sensors import FrameTransformerCfg, ImuCfg
from simlab.tasks.manager_based.classic.cartpole.cartpole_env_cfg import CartpoleEnvCfg, CartpoleSceneCfg
from simlab.utils import configclass
from simlab.utils.errors import ConfigError


@pytest.fixture(autouse=True)
def _fresh_simulation():
    yield
    sim_utils.SimulationContext.clear_instance()


def build_scene(scene_cfg, device: str = "cpu", dt: float = 0.01):
    sim = sim_utils.SimulationContext(sim_utils.SimulationCfg(dt=dt, device=device))
    scene = InteractiveScene(scene_cfg)
    sim.reset()
    return sim, scene


def cartpole_scene(num_envs: int = 2, **robot_fields):
    @configclass
    class SceneCfg(InteractiveSceneCfg):
        ground = AssetBaseCfg(prim_path="/World/ground", spawn=sim_utils.GroundPlaneCfg())
        robot = CARTPOLE_CFG.replace(prim_path="{ENV_REGEX_NS}/Robot", **robot_fields)

    return SceneCfg(num_envs=num_envs, env_spacing=4.0)


# -- SimulationCfg.seed -------------------------------------------------------------------------------


def test_simulation_seed_is_refused_with_where_to_seed():
    with pytest.raises(ConfigError, match=r"SimulationCfg.seed=3 .*nothing in the simulation to seed.*env_cfg.seed"):
        sim_utils.SimulationContext(sim_utils.SimulationCfg(device="cpu", seed=3))
    sim_utils.SimulationContext(sim_utils.SimulationCfg(device="cpu", seed=None))  # the default loads


def test_physx_ccd_is_refused_and_physx_tuning_is_accepted():
    cfg = sim_utils.SimulationCfg(device="cpu")
    cfg.physx.enable_ccd = True
    with pytest.raises(ConfigError, match=r"SimulationCfg.physx.enable_ccd=True .*no continuous collision detection"):
        sim_utils.SimulationContext(cfg)
    cfg = sim_utils.SimulationCfg(device="cpu")
    cfg.physx.bounce_threshold_velocity, cfg.physx.gpu_max_rigid_patch_count = 0.01, 10 * 2**15  # PhysX's tuning
    sim_utils.SimulationContext(cfg)


# -- collision_group ----------------------------------------------------------------------------------


def test_collision_group_minus_one_holds_for_global_assets_only():
    scene_cfg = cartpole_scene()
    scene_cfg.ground.collision_group = -1  # the ground is in every world: collides with every env, as asked
    _, scene = build_scene(scene_cfg)
    assert "ground" in scene
    sim_utils.SimulationContext.clear_instance()

    with pytest.raises(ConfigError, match=r"collision_group=-1 is not supported.*own MuJoCo world.*under /World"):
        build_scene(cartpole_scene(collision_group=-1))
    sim_utils.SimulationContext.clear_instance()
    bad = cartpole_scene()
    bad.ground.collision_group = 3
    with pytest.raises(ConfigError, match=r"collision_group=3: use 0 .* or -1"):
        build_scene(bad)


# -- debug_vis ----------------------------------------------------------------------------------------


def test_debug_vis_on_assets_and_sensors_is_refused():
    with pytest.raises(ConfigError, match=r"Robot'\).debug_vis=True is not supported.*VisualizationMarkers"):
        build_scene(cartpole_scene(debug_vis=True))
    sim_utils.SimulationContext.clear_instance()

    @configclass
    class SensorSceneCfg(InteractiveSceneCfg):
        robot = CARTPOLE_CFG.replace(prim_path="{ENV_REGEX_NS}/Robot")
        imu = ImuCfg(prim_path="{ENV_REGEX_NS}/Robot/pole", debug_vis=True)  # contact sensors draw theirs

    with pytest.raises(ConfigError, match=r"ImuCfg\(.*\).debug_vis=True .*Imu draws no debug"):
        build_scene(SensorSceneCfg(num_envs=2, env_spacing=4.0))


def _cartpole_env_cfg() -> CartpoleEnvCfg:
    cfg = CartpoleEnvCfg()
    cfg.scene.num_envs = 2
    cfg.sim.device = "cpu"
    cfg.seed = 0
    return cfg


def test_debug_vis_on_action_terms_and_undrawn_commands_is_refused():
    cfg = _cartpole_env_cfg()
    cfg.actions.joint_effort.debug_vis = True
    with pytest.raises(ConfigError, match=r"JointEffortActionCfg.debug_vis=True .*env.actions.<term>.debug_vis=false"):
        ManagerBasedRLEnv(cfg)
    sim_utils.SimulationContext.clear_instance()

    @configclass
    class Commands:
        nothing = mdp.NullCommandCfg(debug_vis=True)

    cfg = _cartpole_env_cfg()
    cfg.commands = Commands()
    with pytest.raises(ConfigError, match=r"NullCommandCfg.debug_vis=True .*NullCommand draws no debug"):
        ManagerBasedRLEnv(cfg)


@configclass
class _SidewaysCommand:
    base_velocity = mdp.UniformVelocityCommandCfg(
        asset_name="robot",
        resampling_time_range=(10.0, 10.0),
        debug_vis=True,
        ranges=mdp.UniformVelocityCommandCfg.Ranges(lin_vel_x=(0.0, 0.0), lin_vel_y=(1.0, 1.0), ang_vel_z=(0, 0)),
    )


def _green_pixels(debug_vis: bool) -> int:
    cfg = _cartpole_env_cfg()
    cfg.scene.num_envs = 1
    cfg.commands = _SidewaysCommand()
    cfg.commands.base_velocity.debug_vis = debug_vis
    env = ManagerBasedRLEnv(cfg, render_mode="rgb_array")
    try:
        env.reset()
        env.step(torch.zeros(1, 1))
        assert env.command_manager.has_debug_vis_implementation
        image = env.render().astype(int)
    finally:
        env.close()
    red, green, blue = image[..., 0], image[..., 1], image[..., 2]
    return int(((green > 120) & (red < 100) & (blue < 100)).sum())


def test_velocity_command_debug_vis_draws_the_commanded_velocity():
    """As in Isaac Lab's locomotion configs: debug_vis=True draws the command as a green arrow above the robot."""
    if not rendering_available():
        pytest.skip("no offscreen OpenGL backend (install libosmesa6 or an EGL driver)")
    assert _green_pixels(debug_vis=False) == 0
    assert _green_pixels(debug_vis=True) > 30  # a 1.5 m arrow seen from the side
    assert _green_pixels(debug_vis=False) == 0  # a closed env's arrows are gone


def _frame_marker_image(debug_vis: bool) -> np.ndarray:
    @configclass
    class SceneCfg(CartpoleSceneCfg):
        pole_frame = FrameTransformerCfg(  # Isaac Lab's cabinet config draws its frames so
            prim_path="{ENV_REGEX_NS}/Robot/cart",
            debug_vis=debug_vis,
            target_frames=[FrameTransformerCfg.FrameCfg(prim_path="{ENV_REGEX_NS}/Robot/pole")],
        )

    cfg = _cartpole_env_cfg()
    cfg.scene = SceneCfg(num_envs=1, env_spacing=4.0)
    env = ManagerBasedRLEnv(cfg, render_mode="rgb_array")
    try:
        env.reset()
        env.step(torch.zeros(1, 1))
        assert env.scene["pole_frame"].has_debug_vis_implementation
        return env.render()
    finally:
        env.close()


def test_frame_transformer_debug_vis_draws_its_target_frames():
    if not rendering_available():
        pytest.skip("no offscreen OpenGL backend (install libosmesa6 or an EGL driver)")
    plain, drawn = (_frame_marker_image(v).astype(int) for v in (False, True))
    changed = np.abs(drawn - plain).sum(-1) > 60
    assert changed.sum() > 50  # the marker at the pole's frame (and its reflection in the floor)
    for axis in range(3):  # x red, y green, z blue: each axis drawn in its own colour
        others = np.delete(drawn, axis, axis=-1)
        coloured = (drawn[..., axis] > 50) & (drawn[..., axis] > 2 * others.max(-1))
        assert (coloured & changed).sum() > 3, f"no {'xyz'[axis]} axis"


# -- InteractiveSceneCfg ------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("field", "message"),
    [
        ("filter_collisions", r"filter_collisions=False .*cannot collide with each other"),
    ],
)
def test_scene_settings_simlab_cannot_honour_are_refused(field, message):
    scene_cfg = cartpole_scene()
    setattr(scene_cfg, field, False)
    with pytest.raises(ConfigError, match=message):
        build_scene(scene_cfg)


def test_speed_only_scene_settings_give_the_same_simulation():
    """lazy_sensor_update and clone_in_fabric only change speed in Isaac Lab: both values load and simulate alike."""
    states = []
    for lazy, fabric in ((True, False), (False, True)):
        scene_cfg = cartpole_scene()
        scene_cfg.lazy_sensor_update, scene_cfg.clone_in_fabric = lazy, fabric
        sim, scene = build_scene(scene_cfg)
        robot = scene["robot"]
        robot.set_joint_effort_target(torch.full((2, 1), 20.0), joint_ids=[0])
        for _ in range(20):
            scene.write_data_to_sim()
            sim.step()
            scene.update(sim.get_physics_dt())
        states.append(robot.data.joint_pos.clone())
        sim_utils.SimulationContext.clear_instance()
    torch.testing.assert_close(states[0], states[1])


# -- joint velocity limits ----------------------------------------------------------------------------


def _push_cart(actuator_cfg, device: str, steps: int = 60, limit_at_runtime: float | None = None) -> torch.Tensor:
    """Largest cart speed over ``steps`` physics steps of a constant 60 N push."""
    sim, scene = build_scene(cartpole_scene(actuators={"cart": actuator_cfg}), device)
    robot = scene["robot"]
    if limit_at_runtime is not None:
        robot.write_joint_velocity_limit_to_sim(torch.full((2, 1), limit_at_runtime), joint_ids=[0])
    robot.set_joint_effort_target(torch.full((2, 1), 60.0, device=sim.device), joint_ids=[0])
    fastest = torch.zeros(2, device=sim.device)
    for _ in range(steps):
        scene.write_data_to_sim()
        sim.step()
        scene.update(sim.get_physics_dt())
        fastest = torch.maximum(fastest, robot.data.joint_vel[:, 0].abs())
    sim_utils.SimulationContext.clear_instance()
    return fastest.cpu()


# one 10 ms step of a 60 N push on the cart adds at most this much speed after the cap [m/s]
_ONE_STEP = 0.6


@pytest.mark.parametrize("device", DEVICES)
@pytest.mark.parametrize("kind", [ImplicitActuatorCfg, IdealPDActuatorCfg])
def test_velocity_limit_sim_caps_the_joint_speed(device, kind):
    free = _push_cart(kind(joint_names_expr=["slider_to_cart"], stiffness=0.0, damping=0.0), device)
    assert (free > 3.0).all(), f"without a cap the cart reaches {free.tolist()} m/s"
    capped = _push_cart(
        kind(joint_names_expr=["slider_to_cart"], stiffness=0.0, damping=0.0, velocity_limit_sim=1.0), device
    )
    assert (capped <= 1.0 + _ONE_STEP).all() and (capped >= 1.0).all(), capped.tolist()


def test_joint_velocity_limit_written_at_runtime_caps_the_speed():
    cfg = ImplicitActuatorCfg(joint_names_expr=["slider_to_cart"], stiffness=0.0, damping=0.0)
    capped = _push_cart(cfg, "cpu", limit_at_runtime=0.5)
    assert (capped <= 0.5 + _ONE_STEP).all(), capped.tolist()


def test_implicit_velocity_limit_follows_isaac_lab():
    """Isaac Lab's implicit drives ignore a lone ``velocity_limit`` (with a warning) and refuse two different ones."""
    cfg = ImplicitActuatorCfg(joint_names_expr=["slider_to_cart"], stiffness=0.0, damping=0.0, velocity_limit=1.0)
    with pytest.warns(UserWarning, match="'velocity_limit' does not limit an implicit drive.*velocity_limit_sim"):
        free = _push_cart(cfg, "cpu")
    assert (free > 3.0).all()
    both = cfg.replace(velocity_limit_sim=2.0)
    with pytest.raises(
        ConfigError, match="velocity_limit=1.0 and velocity_limit_sim=2.0.*set only 'velocity_limit_sim'"
    ):
        _push_cart(both, "cpu")


def test_dc_motor_curve_uses_its_own_velocity_limit():
    """A DC motor's no-load speed is ``velocity_limit``; ``velocity_limit_sim`` is the simulation's cap."""
    cfg = DCMotorCfg(
        joint_names_expr=["slider_to_cart"],
        stiffness=0.0,
        damping=0.0,
        saturation_effort=100.0,
        effort_limit=80.0,
        velocity_limit=2.0,
        velocity_limit_sim=50.0,
    )
    sim, scene = build_scene(cartpole_scene(num_envs=1, actuators={"cart": cfg}))
    robot = scene["robot"]
    robot.write_joint_state_to_sim(torch.zeros(1, 2), torch.tensor([[1.0, 0.0]]))
    robot.set_joint_effort_target(torch.full((1, 1), 500.0), joint_ids=[0])
    robot.write_data_to_sim()
    assert robot.actuators["cart"].applied_effort[0, 0].item() == pytest.approx(50.0)  # 100 * (1 - 1/2)
    assert robot.data.joint_velocity_limits[0, 0].item() == pytest.approx(50.0)


def test_a_deformable_object_as_isaac_labs_tutorial_writes_it_is_one_line_of_refusal():
    """Isaac Lab's run_deformable_object.py tutorial: its soft cube's settings (every field of Isaac Lab's
    DeformableBodyPropertiesCfg is accepted) reach DeformableObjectCfg, which refuses in one line."""
    from simlab.assets import DeformableObjectCfg

    props = sim_utils.DeformableBodyPropertiesCfg(
        rest_offset=0.0, contact_offset=0.001, self_collision_filter_distance=0.01, settling_threshold=0.1,
        sleep_damping=10.0, sleep_threshold=0.05, collision_simplification=True,
        collision_simplification_remeshing=True, collision_simplification_remeshing_resolution=0,
        collision_simplification_target_triangle_count=0, collision_simplification_force_conforming=True,
        max_depenetration_velocity=1.0,
    )  # fmt: skip
    spawn = sim_utils.MeshCuboidCfg(
        size=(0.2, 0.2, 0.2),
        deformable_props=props,
        physics_material=sim_utils.DeformableBodyMaterialCfg(poissons_ratio=0.4, youngs_modulus=1e5),
    )
    with pytest.raises(ConfigError) as err:
        DeformableObjectCfg(prim_path="/World/Origin.*/Cube", spawn=spawn)
    assert "\n" not in str(err.value) and "RigidObjectCfg" in str(err.value)
