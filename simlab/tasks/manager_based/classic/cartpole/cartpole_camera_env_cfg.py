"""Cartpole from pixels, manager-based (Isaac Lab's ``cartpole_camera_env_cfg``: ``Isaac-Cartpole-RGB-v0``
and ``Isaac-Cartpole-Depth-v0``).

The cart, pole, actions, events, rewards and terminations of :mod:`.cartpole_env_cfg`; the policy sees
only a 100 x 100 image of its env from a tiled camera in front of the rail (``mdp.image``: RGB in
[0, 1] minus each image's mean colour, or the distance to the camera in metres, 0 where nothing is hit).
Envs stand 20 m apart so that no camera sees a neighbour.

One image shows where the pole is, not how fast it turns: a policy sees the last k with
``env.observations.policy.image.history_length=k`` and ``flatten_history_dim=False`` (rsl_rl's wrapper
stacks a history's images along the channels). A ``teacher`` group holds the state cartpole's
observations (joint positions and velocities) for distillation: the state cartpole's PPO policy teaches a
student that sees the images only (``--agent rsl_rl_distillation_cfg_entry_point``; docs/cameras.md).
"""

from __future__ import annotations

import simlab.sim as sim_utils
from simlab.managers import ObservationGroupCfg as ObsGroup
from simlab.managers import ObservationTermCfg as ObsTerm
from simlab.managers import SceneEntityCfg
from simlab.sensors import TiledCameraCfg
from simlab.utils import configclass

from . import mdp
from .cartpole_env_cfg import CartpoleEnvCfg, CartpoleSceneCfg, ObservationsCfg


def _camera(data_type: str) -> TiledCameraCfg:
    return TiledCameraCfg(
        prim_path="{ENV_REGEX_NS}/Camera",
        # 7 m in front of the rail and 3 m up, pitched 12 degrees down at the cart (world convention)
        offset=TiledCameraCfg.OffsetCfg(pos=(-7.0, 0.0, 3.0), rot=(0.9945, 0.0, 0.1045, 0.0), convention="world"),
        data_types=[data_type],
        spawn=sim_utils.PinholeCameraCfg(
            focal_length=24.0, focus_distance=400.0, horizontal_aperture=20.955, clipping_range=(0.1, 20.0)
        ),
        width=100,
        height=100,
    )


@configclass
class CartpoleRGBCameraSceneCfg(CartpoleSceneCfg):
    tiled_camera: TiledCameraCfg = _camera("rgb")


@configclass
class CartpoleDepthCameraSceneCfg(CartpoleSceneCfg):
    tiled_camera: TiledCameraCfg = _camera("distance_to_camera")


@configclass
class RGBObservationsCfg:
    @configclass
    class RGBCameraPolicyCfg(ObsGroup):
        image = ObsTerm(func=mdp.image, params={"sensor_cfg": SceneEntityCfg("tiled_camera"), "data_type": "rgb"})

        def __post_init__(self) -> None:
            self.enable_corruption = False
            self.concatenate_terms = True

    policy: ObsGroup = RGBCameraPolicyCfg()
    # the state cartpole's observations, for a teacher only (distillation): no policy of the image reads it
    teacher: ObsGroup = ObservationsCfg.PolicyCfg()


@configclass
class DepthObservationsCfg:
    @configclass
    class DepthCameraPolicyCfg(RGBObservationsCfg.RGBCameraPolicyCfg):
        image = ObsTerm(
            func=mdp.image, params={"sensor_cfg": SceneEntityCfg("tiled_camera"), "data_type": "distance_to_camera"}
        )

    policy: ObsGroup = DepthCameraPolicyCfg()
    teacher: ObsGroup = ObservationsCfg.PolicyCfg()


@configclass
class CartpoleRGBCameraEnvCfg(CartpoleEnvCfg):
    scene: CartpoleSceneCfg = CartpoleRGBCameraSceneCfg(num_envs=512, env_spacing=20.0)
    observations: RGBObservationsCfg = RGBObservationsCfg()

    def __post_init__(self) -> None:
        super().__post_init__()
        self.viewer.eye = (7.0, 0.0, 2.5)
        self.viewer.lookat = (0.0, 0.0, 2.5)
        self.final_observations = False  # one render per step (the agents here do not read extras["final_obs"])


@configclass
class CartpoleDepthCameraEnvCfg(CartpoleEnvCfg):
    scene: CartpoleSceneCfg = CartpoleDepthCameraSceneCfg(num_envs=512, env_spacing=20.0)
    observations: DepthObservationsCfg = DepthObservationsCfg()

    def __post_init__(self) -> None:
        super().__post_init__()
        self.viewer.eye = (7.0, 0.0, 2.5)
        self.viewer.lookat = (0.0, 0.0, 2.5)
        self.final_observations = False  # one render per step (the agents here do not read extras["final_obs"])
