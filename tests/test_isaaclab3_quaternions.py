"""Isaac Lab 3.0's (x, y, z, w) quaternions beside 2.x's (w, x, y, z) in one process (simlab.v3, issue 42.1
and 42.4): the order of a value is the order of the namespace its name comes from, never a guess."""

from __future__ import annotations

import math
from pathlib import Path

import pytest
import torch
from conftest import load_script

import simlab.sim as sim_utils
import simlab.utils.math as math2
import simlab.v3.utils.math as math3
from simlab import assets as assets2
from simlab import scene as scene2
from simlab.utils.errors import ConfigError
from simlab.v3 import assets as assets3
from simlab.v3 import scene as scene3
from simlab.v3._order import to_simlab

PORTED3 = Path(__file__).parent / "ported3" / "cartpole_v3_env_cfg.py"

# one rotation, written in each order: a quarter turn about z, then 30 degrees about the new x
C, S = math.cos(math.pi / 4), math.sin(math.pi / 4)
Q_WXYZ = math2.quat_mul(
    torch.tensor([C, 0.0, 0.0, S]), torch.tensor([math.cos(math.pi / 12), math.sin(math.pi / 12), 0, 0])
)
Q_XYZW = math3.xyzw_from_wxyz(Q_WXYZ)


def test_v3_math_is_simlab_math_in_xyzw_order():
    roll, pitch, yaw = torch.tensor([0.3]), torch.tensor([-0.2]), torch.tensor([1.1])
    q2 = math2.quat_from_euler_xyz(roll, pitch, yaw)
    q3 = math3.quat_from_euler_xyz(roll, pitch, yaw)
    assert torch.allclose(q3, q2[:, [1, 2, 3, 0]])
    assert torch.allclose(math3.quat_from_euler_xyz(*(torch.zeros(1),) * 3), torch.tensor([[0.0, 0.0, 0.0, 1.0]]))
    vec = torch.tensor([[1.0, 2.0, 3.0]])
    assert torch.allclose(math3.quat_apply(q3, vec), math2.quat_apply(q2, vec))
    assert torch.allclose(math3.quat_mul(q3, q3), math3.xyzw_from_wxyz(math2.quat_mul(q2, q2)))
    assert torch.allclose(math3.matrix_from_quat(q3), math2.matrix_from_quat(q2))
    t, q = math3.combine_frame_transforms(vec, q3, vec, q3)
    t2, q2b = math2.combine_frame_transforms(vec, q2, vec, q2)
    assert torch.allclose(t, t2) and torch.allclose(q, math3.xyzw_from_wxyz(q2b))
    _, err = math3.compute_pose_error(vec, q3, vec, q3, rot_error_type="quat")
    assert torch.allclose(err.abs(), torch.tensor([[0.0, 0.0, 0.0, 1.0]]), atol=1e-6)  # identity, (x, y, z, w)
    assert torch.equal(math3.wrap_to_pi(torch.tensor([4.0])), math2.wrap_to_pi(torch.tensor([4.0])))  # no quats


def test_v3_math_refuses_what_it_cannot_order(monkeypatch):
    with pytest.raises(AttributeError, match="Isaac Lab 3.0 removed convert_quat"):
        math3.convert_quat  # noqa: B018
    # a quaternion function of simlab's math that the (x, y, z, w) table does not list never leaks through
    monkeypatch.setattr(math2, "twist_of", lambda quat, axis: quat, raising=False)
    with pytest.raises(AttributeError, match=r"twist_of is not offered in \(x, y, z, w\) order yet"):
        math3.twist_of  # noqa: B018
    assert math3.make_pose is math2.make_pose  # its rot is a rotation matrix


def test_a_3_0_config_checks_its_rot_in_one_line():
    with pytest.raises(
        ConfigError, match=r"rot=\(1, 0, 0, 0\) is Isaac Lab 2.x's identity .* whose identity is \(0, 0, 0, 1\)"
    ):
        assets3.RigidObjectCfg.InitialStateCfg(rot=(1, 0, 0, 0))
    with pytest.raises(ConfigError, match="is not a unit quaternion; Isaac Lab 3.0 configs take"):
        assets3.ArticulationCfg.InitialStateCfg(rot=(0.0, 0.0, 0.5, 0.5))
    assert assets3.AssetBaseCfg.InitialStateCfg().rot == (0.0, 0.0, 0.0, 1.0)
    assert assets3.RigidObjectCfg.InitialStateCfg(rot=(-1, 0, 0, 0)).rot == (-1, 0, 0, 0)  # the half turn about x
    assert assets2.RigidObjectCfg.InitialStateCfg(rot=(1, 0, 0, 0)).rot == (1, 0, 0, 0)  # 2.x's identity, as before


def test_3_0_configs_keep_their_order_through_replace_and_convert_once():
    cfg = assets3.RigidObjectCfg(
        prim_path="/World/Box", init_state=assets3.RigidObjectCfg.InitialStateCfg(rot=(0, 0, 1, 0))
    )
    assert cfg.replace(prim_path="/World/Other").init_state.rot == (0, 0, 1, 0)  # what the user wrote, read back
    assert cfg.copy().init_state.rot == (0, 0, 1, 0)
    simlab_cfg = to_simlab(cfg)
    assert (
        simlab_cfg.init_state.rot == (0, 0, 0, 1)
        and type(simlab_cfg.init_state) is assets2.RigidObjectCfg.InitialStateCfg
    )
    assert to_simlab(simlab_cfg) is simlab_cfg  # nothing left to convert
    assert cfg.init_state.rot == (0, 0, 1, 0)  # the user's config is not changed


def _box(cfg_module, rot, y: float):
    return cfg_module.RigidObjectCfg(
        prim_path=f"/World/Box{int(y)}",
        spawn=sim_utils.CuboidCfg(
            size=(0.4, 0.2, 0.1),
            rigid_props=sim_utils.RigidBodyPropertiesCfg(kinematic_enabled=True),
            mass_props=sim_utils.MassPropertiesCfg(mass=1.0),
        ),
        init_state=cfg_module.RigidObjectCfg.InitialStateCfg(pos=(0.0, y, 1.0), rot=tuple(rot.tolist())),
    )


def test_the_same_rotation_in_2_x_and_3_0_configs_gives_the_same_pose():
    from simlab.utils import configclass

    @configclass
    class MixedSceneCfg(scene3.InteractiveSceneCfg):
        box2 = _box(assets2, Q_WXYZ, 1.0)  # a 2.x config: (w, x, y, z)
        box3 = _box(assets3, Q_XYZW, 2.0)  # a 3.0 config: (x, y, z, w)

    sim = sim_utils.SimulationContext(sim_utils.SimulationCfg(device="cpu"))
    scene = scene3.InteractiveScene(MixedSceneCfg(num_envs=2, env_spacing=3.0))
    sim.reset()
    scene.update(sim.get_physics_dt())
    q2 = scene["box2"].data.root_quat_w  # simlab's data: (w, x, y, z)
    q3 = scene["box3"].data.root_quat_w
    assert torch.allclose(q2, Q_WXYZ.expand(2, 4), atol=1e-5)
    assert torch.allclose(q3, q2, atol=1e-5)
    # the box's long side points where the rotation sends x, in both
    x_axis = torch.tensor([[1.0, 0.0, 0.0]]).expand(2, 3)
    assert torch.allclose(math2.quat_apply(q3, x_axis), math3.quat_apply(Q_XYZW.expand(2, 4), x_axis), atol=1e-5)


def test_a_3_0_config_read_by_2_x_code_is_refused_in_one_line():
    """simlab's 2.x scene and assets read (w, x, y, z): a 3.0 ``init_state`` that reaches them unconverted
    (a spawn-only asset of a 2.x scene, a 3.0 state in a 2.x asset config) is refused, saying the order."""
    from simlab.utils import configclass

    light = assets3.AssetBaseCfg(
        prim_path="/World/Light",
        init_state=assets3.AssetBaseCfg.InitialStateCfg(rot=(0.0, 0.7071068, 0.0, 0.7071068)),
        spawn=sim_utils.DistantLightCfg(intensity=1000.0),
    )

    @configclass
    class SceneCfg(scene2.InteractiveSceneCfg):
        light_3_0 = light

    sim_utils.SimulationContext(sim_utils.SimulationCfg(device="cpu"))
    expected = (
        r"init_state is Isaac Lab 3.0's, rot in \(x, y, z, w\) order, but simlab's 2.x asset reads \(w, x, y, z\)"
    )
    with pytest.raises(ConfigError, match=expected):
        scene2.InteractiveScene(SceneCfg(num_envs=1, env_spacing=2.0))
    mixed = _box(assets2, Q_WXYZ, 1.0).replace(init_state=assets3.RigidObjectCfg.InitialStateCfg(rot=(0, 0, 1, 0)))
    with pytest.raises(ConfigError, match=expected):
        assets2.RigidObject(mixed)
    assert scene3.InteractiveScene(SceneCfg(num_envs=1, env_spacing=2.0))  # the 3.0 scene converts it


def _step(env, steps: int = 5) -> torch.Tensor:
    obs, _ = env.reset(seed=3)
    for _ in range(steps):
        obs, *_ = env.step(torch.zeros(env.unwrapped.num_envs, 1))
    return obs["policy"]


def test_a_2_x_task_and_a_3_0_task_run_side_by_side():
    """The registered 2.x cartpole and a task config written for 3.0 (tests/ported3), one process."""
    import gymnasium as gym

    import simlab.envs
    import simlab.tasks  # noqa: F401
    import simlab.v3.envs
    from simlab.sim import SimulationContext
    from simlab.tasks.utils import parse_env_cfg

    cfg2 = parse_env_cfg("simlab/Cartpole-v0", device="cpu", num_envs=4)
    env2 = gym.make("simlab/Cartpole-v0", cfg=cfg2)
    obs2 = _step(env2)
    env2.close()
    SimulationContext.clear_instance()

    ported = load_script(PORTED3, "cartpole_v3_env_cfg")
    cfg3 = ported.CartpoleEnvCfg()
    cfg3.sim.device = "cpu"
    env3 = simlab.v3.envs.ManagerBasedRLEnv(cfg3)
    assert isinstance(env3, simlab.envs.ManagerBasedRLEnv)
    obs3 = _step(env3)
    box = env3.scene["box"].data.root_quat_w  # simlab's (w, x, y, z) of the 3.0 config's (x, y, z, w)
    light_cfg = env3.cfg.scene.distant_light.init_state
    env3.close()
    assert obs2.shape == obs3.shape == (4, 4) and torch.isfinite(obs2).all() and torch.isfinite(obs3).all()
    assert torch.allclose(box, math3.wxyz_from_xyzw(torch.tensor(ported.BOX_ROT_XYZW)).expand(4, 4), atol=1e-5)
    assert light_cfg.rot == (0.7071068, 0.0, 0.7071068, 0.0)  # converted once, for simlab's readers
    assert cfg3.scene.distant_light.init_state.rot == (0.0, 0.7071068, 0.0, 0.7071068)  # as written


def test_a_sensor_offset_in_either_order_gives_the_same_sensor_frame():
    from simlab import sensors as sensors2
    from simlab.utils import configclass
    from simlab.v3 import sensors as sensors3

    @configclass
    class SceneCfg(scene3.InteractiveSceneCfg):
        box = _box(assets2, Q_WXYZ, 1.0).replace(prim_path="{ENV_REGEX_NS}/Box")
        box_b = _box(assets2, Q_WXYZ, 2.0).replace(prim_path="{ENV_REGEX_NS}/BoxB")
        imu2 = sensors2.ImuCfg(
            prim_path="{ENV_REGEX_NS}/Box", offset=sensors2.ImuCfg.OffsetCfg(rot=tuple(Q_WXYZ.tolist()))
        )
        imu3 = sensors3.ImuCfg(
            prim_path="{ENV_REGEX_NS}/BoxB", offset=sensors3.ImuCfg.OffsetCfg(rot=tuple(Q_XYZW.tolist()))
        )

    sim = sim_utils.SimulationContext(sim_utils.SimulationCfg(device="cpu"))
    scene = scene3.InteractiveScene(SceneCfg(num_envs=2, env_spacing=3.0))
    sim.reset()
    scene.update(sim.get_physics_dt())
    q2, q3 = scene["imu2"].data.quat_w, scene["imu3"].data.quat_w
    expected = math2.quat_mul(Q_WXYZ, Q_WXYZ).expand(2, 4)  # the box's rotation, then the offset's
    assert torch.allclose(math2.quat_unique(q2), math2.quat_unique(expected), atol=1e-4)
    assert torch.allclose(math2.quat_unique(q3), math2.quat_unique(q2), atol=1e-5)


def test_a_3_0_sensor_offset_in_a_2_x_scene_is_refused():
    from simlab.utils import configclass
    from simlab.v3 import sensors as sensors3

    @configclass
    class SceneCfg(scene2.InteractiveSceneCfg):
        box = _box(assets2, Q_WXYZ, 1.0).replace(prim_path="{ENV_REGEX_NS}/Box")
        imu = sensors3.ImuCfg(prim_path="{ENV_REGEX_NS}/Box", offset=sensors3.ImuCfg.OffsetCfg(rot=(0, 0, 1, 0)))

    sim_utils.SimulationContext(sim_utils.SimulationCfg(device="cpu"))
    with pytest.raises(ConfigError, match=r"ImuCfg\('.*Box'\).offset is Isaac Lab 3.0's, rot in \(x, y, z, w\) order"):
        scene2.InteractiveScene(SceneCfg(num_envs=1, env_spacing=2.0))
