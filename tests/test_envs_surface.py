"""Isaac Lab's env-side helpers: space (de)serialization, term-config curricula, markers, env windows."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest
import torch

import simlab.envs.mdp as mdp
from simlab.envs import ManagerBasedRLEnv
from simlab.envs.ui import BaseEnvWindow, ViewportCameraController
from simlab.envs.utils import (
    deserialize_space,
    replace_env_cfg_spaces_with_strings,
    replace_strings_with_env_cfg_spaces,
    serialize_space,
)
from simlab.managers import CurriculumTermCfg as CurrTerm
from simlab.markers import (
    FRAME_MARKER_CFG,
    POSITION_GOAL_MARKER_CFG,
    RED_ARROW_X_MARKER_CFG,
    VisualizationMarkers,
    VisualizationMarkersCfg,
)
from simlab.sim import SphereCfg, UsdFileCfg
from simlab.tasks.manager_based.classic.cartpole.cartpole_env_cfg import CartpoleEnvCfg
from simlab.utils import configclass

# -- spaces ----------------------------------------------------------------------------------------

SPACES = [
    gym.spaces.Box(low=-1.0, high=2.0, shape=(3,)),
    gym.spaces.Box(low=np.array([0.0, -1.0]), high=np.array([1.0, 5.0]), dtype=np.float64),
    gym.spaces.Discrete(5, start=2),
    gym.spaces.MultiDiscrete([3, 4]),
    gym.spaces.Dict({"a": gym.spaces.Box(-1, 1, (2,)), "b": gym.spaces.Tuple((gym.spaces.Discrete(2),))}),
]
SPECS = [7, [64, 64, 3], {2}, [{2}, {5}], {"a": 7, "b": {2}}, (7, {2}, [1, 2])]


@pytest.mark.parametrize("space", SPACES, ids=lambda s: type(s).__name__)
def test_gymnasium_spaces_round_trip(space):
    back = deserialize_space(serialize_space(space))
    assert back == space and type(back) is type(space)


@pytest.mark.parametrize("spec", SPECS, ids=str)
def test_python_space_specs_round_trip(spec):
    assert deserialize_space(serialize_space(spec)) == spec


def test_space_serialization_errors_and_cfg_helpers():
    with pytest.raises(ValueError, match="Cannot serialize the space spec"):
        serialize_space("seven")
    with pytest.raises(ValueError, match="Not a serialized space"):
        deserialize_space("{}")

    class Cfg:
        observation_space = {"policy": 4}
        action_space = {1}
        state_space = None
        observation_spaces = {"a": 3, "b": [2, 2]}

    cfg = replace_env_cfg_spaces_with_strings(Cfg())
    assert all(isinstance(v, str) for v in (cfg.observation_space, cfg.action_space, *cfg.observation_spaces.values()))
    assert cfg.state_space is None
    replace_strings_with_env_cfg_spaces(cfg)
    assert cfg.observation_space == {"policy": 4} and cfg.action_space == {1}
    assert cfg.observation_spaces == {"a": 3, "b": [2, 2]}


# -- curricula -------------------------------------------------------------------------------------


def cartpole(num_envs: int = 2, **fields) -> CartpoleEnvCfg:
    cfg = CartpoleEnvCfg()
    cfg.scene.num_envs = num_envs
    cfg.sim.device = "cpu"
    cfg.seed = 0
    for key, value in fields.items():
        setattr(cfg, key, value)
    return cfg


def test_modify_term_cfg_reaches_manager_configs_and_tuple_items():
    def after(env, env_ids, old, value, num_steps):
        return value if env.common_step_counter >= num_steps else mdp.modify_term_cfg.NO_CHANGE

    @configclass
    class Curriculum:
        alive = CurrTerm(
            func=mdp.modify_term_cfg,
            params={
                "address": "rewards.alive.weight",
                "modify_fn": after,
                "modify_params": {"value": 3.0, "num_steps": 2},
            },
        )
        cart_upper = CurrTerm(
            func=mdp.modify_term_cfg,
            params={
                "address": "events.reset_cart_position.params.position_range[1]",
                "modify_fn": after,
                "modify_params": {"value": 0.25, "num_steps": 2},
            },
        )

    env = ManagerBasedRLEnv(cartpole(curriculum=Curriculum()))
    env.reset()
    before = env.event_manager.get_term_cfg("reset_cart_position").params["position_range"]
    for _ in range(3):
        env.step(torch.zeros(2, 1))
    env.reset()
    assert env.reward_manager.get_term_cfg("alive").weight == 3.0
    after_range = env.event_manager.get_term_cfg("reset_cart_position").params["position_range"]
    assert isinstance(after_range, tuple) and after_range == (before[0], 0.25)  # the tuple was rebuilt
    env.close()


def test_curriculum_addresses_are_checked_when_the_env_is_built():
    @configclass
    class Curriculum:
        bad = CurrTerm(func=mdp.modify_term_cfg, params={"address": "rewards.not_a_term.weight", "modify_fn": None})

    with pytest.raises(ValueError, match="'reward_manager.cfg.not_a_term' of address"):
        ManagerBasedRLEnv(cartpole(curriculum=Curriculum()))


# -- markers ---------------------------------------------------------------------------------------


def test_markers_are_drawn_into_the_rendered_env_only():
    cfg = cartpole()
    cfg.viewer.resolution = (160, 120)
    cfg.viewer.eye, cfg.viewer.lookat, cfg.viewer.origin_type = (6.0, 0.0, 3.0), (0.0, 0.0, 1.0), "env"
    env = ManagerBasedRLEnv(cfg, render_mode="rgb_array")
    env.reset()
    try:
        plain = env.render().astype(np.int32)
    except RuntimeError as err:  # no OpenGL on this machine
        env.close()
        pytest.skip(f"offscreen rendering unavailable: {err}")
    origins = env.scene.env_origins
    goal = VisualizationMarkers(POSITION_GOAL_MARKER_CFG.replace(prim_path="/Visuals/goal"))
    # a big green sphere beside the cart of env 1 only: env 0's image must not change
    goal.visualize(origins[1:] + torch.tensor([0.0, 1.0, 1.0]), marker_indices=[1], scales=torch.full((1, 3), 30.0))
    assert np.array_equal(env.render().astype(np.int32), plain)
    goal.visualize(origins[:1] + torch.tensor([0.0, 1.0, 1.0]))
    marked = env.render().astype(np.int32)
    changed = np.abs(marked - plain).sum(-1) > 30
    assert changed.sum() > 50
    green = marked[changed]
    assert (green[:, 1] > green[:, 0] + 40).mean() > 0.8  # the "target_near" prototype is green
    goal.set_visibility(False)
    assert np.array_equal(env.render().astype(np.int32), plain)
    # arrows and frames draw too
    arrows = VisualizationMarkers(RED_ARROW_X_MARKER_CFG.replace(prim_path="/Visuals/arrow"))
    arrows.visualize(origins + torch.tensor([0.0, 0.0, 2.0]), scales=torch.tensor([[2.0, 3.0, 3.0]] * 2))
    frames = VisualizationMarkers(FRAME_MARKER_CFG.replace(prim_path="/Visuals/frame"))
    frames.visualize(origins + torch.tensor([0.0, -1.0, 1.0]))
    # 48 pixels at 160x120 since offscreen frames skip multisampling (the arrow is seen head-on)
    assert (np.abs(env.render().astype(np.int32) - plain).sum(-1) > 30).sum() > 40
    env.close()


def test_marker_errors():
    with pytest.raises(ValueError, match="cannot be drawn"):
        VisualizationMarkers(VisualizationMarkersCfg(prim_path="/V", markers={"m": UsdFileCfg(usd_path="robot.usd")}))
    arrow = VisualizationMarkers(
        VisualizationMarkersCfg(
            prim_path="/V", markers={"a": UsdFileCfg(usd_path="x/arrow_x.usd", scale=(1, 0.1, 0.1))}
        )
    )
    assert arrow.num_prototypes == 1
    markers = VisualizationMarkers(VisualizationMarkersCfg(prim_path="/V", markers={"s": SphereCfg(radius=0.1)}))
    markers.visualize([[0.0, 0.0, 1.0], [1.0, 0.0, 1.0]], marker_indices=[0, 0])  # plain lists work too
    assert markers.count == 2
    with pytest.raises(ValueError, match="shape \\(M, 3\\)"):
        markers.visualize(torch.zeros(4, 2))
    with pytest.raises(ValueError, match="marker_indices must be in \\[0, 0\\]"):
        markers.visualize(torch.zeros(2, 3), marker_indices=[0, 1])
    with pytest.raises(ValueError, match="orientations has 3 rows but there are 2 markers"):
        markers.visualize(torch.zeros(2, 3), orientations=torch.zeros(3, 4))


def test_env_windows_are_refused_headless():
    assert issubclass(type("QuadcopterEnvWindow", (BaseEnvWindow,), {}), BaseEnvWindow)
    with pytest.raises(RuntimeError, match="no GUI"):
        BaseEnvWindow(env=None)
    with pytest.raises(RuntimeError, match="env.cfg.viewer"):
        ViewportCameraController(env=None, cfg=None)
