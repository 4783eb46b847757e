"""Cartpole from pixels, direct workflow (Isaac Lab's ``Isaac-Cartpole-RGB-Camera-Direct-v0`` and
``Isaac-Cartpole-Depth-Camera-Direct-v0``).

The same cart, pole, actions, rewards and terminations as :mod:`.cartpole_env`; the policy sees only
a 100 x 100 image of its env from a camera 5 m in front of the rail: RGB scaled to [0, 1] minus each
image's mean colour, or depth in metres (0 where nothing is hit). Envs stand 20 m apart, as in
Isaac Lab, so that no camera sees a neighbour.
"""

from __future__ import annotations

import gymnasium as gym
import torch

import simlab.sim as sim_utils
from simlab.assets import Articulation, ArticulationCfg
from simlab.envs import DirectRLEnvCfg
from simlab.envs.common import ViewerCfg
from simlab.robots.cartpole import CARTPOLE_CFG
from simlab.scene import InteractiveSceneCfg
from simlab.sensors import TiledCamera, TiledCameraCfg
from simlab.sim import SimulationCfg
from simlab.utils import configclass

from .cartpole_env import CartpoleEnv


def _camera_cfg(data_type: str) -> TiledCameraCfg:
    return TiledCameraCfg(
        prim_path="/World/envs/env_.*/Camera",
        # 5 m in front of the rail, looking along +x at the cart (world convention: forward +x, up +z)
        offset=TiledCameraCfg.OffsetCfg(pos=(-5.0, 0.0, 2.0), rot=(1.0, 0.0, 0.0, 0.0), convention="world"),
        data_types=[data_type],
        spawn=sim_utils.PinholeCameraCfg(
            focal_length=24.0, focus_distance=400.0, horizontal_aperture=20.955, clipping_range=(0.1, 20.0)
        ),
        width=100,
        height=100,
    )


@configclass
class CartpoleRGBCameraEnvCfg(DirectRLEnvCfg):
    # env
    decimation = 2
    episode_length_s = 5.0
    action_scale = 100.0  # [N]
    final_observations = False  # one render per step (the agents here do not read extras["final_obs"])

    # simulation
    sim: SimulationCfg = SimulationCfg(dt=1 / 120, render_interval=decimation)

    # robot
    robot_cfg: ArticulationCfg = CARTPOLE_CFG.replace(prim_path="/World/envs/env_.*/Robot")
    cart_dof_name = "slider_to_cart"
    pole_dof_name = "cart_to_pole"

    # camera
    tiled_camera: TiledCameraCfg = _camera_cfg("rgb")
    write_image_to_file = False
    frame_stack = 1
    """Images per observation, newest last along the channel axis (1: Isaac Lab's layout). One image
    shows where the pole is but not how fast it turns, which balancing needs; 2 shows both."""

    # spaces
    action_space = 1
    state_space = 0
    observation_space = [tiled_camera.height, tiled_camera.width, 3]

    # Isaac Lab's eye (20, 20, 20) frames its grid of envs 20 m apart; a video shows env 0, which
    # from there is a few pixels on a floorless scene, so the eye comes as close as the cartpole's
    viewer = ViewerCfg(eye=(5.0, 5.0, 4.5), lookat=(0.0, 0.0, 2.5))

    # scene
    scene: InteractiveSceneCfg = InteractiveSceneCfg(num_envs=512, env_spacing=20.0, replicate_physics=True)

    # reset
    max_cart_pos = 3.0  # the cart is reset beyond this position [m]
    initial_pole_angle_range = [-0.125, 0.125]  # pole angle at reset, in units of pi [rad / pi]

    # reward scales
    rew_scale_alive = 1.0
    rew_scale_terminated = -2.0
    rew_scale_pole_pos = -1.0
    rew_scale_cart_vel = -0.01
    rew_scale_pole_vel = -0.005


@configclass
class CartpoleDepthCameraEnvCfg(CartpoleRGBCameraEnvCfg):
    tiled_camera: TiledCameraCfg = _camera_cfg("depth")
    observation_space = [tiled_camera.height, tiled_camera.width, 1]


class CartpoleCameraEnv(CartpoleEnv):
    """The cartpole env with a camera's image as its observation (actions, rewards, dones and resets
    are the state cartpole's)."""

    cfg: CartpoleRGBCameraEnvCfg | CartpoleDepthCameraEnvCfg

    def __init__(self, cfg: CartpoleRGBCameraEnvCfg, render_mode: str | None = None, **kwargs):
        if not isinstance(cfg.frame_stack, int) or cfg.frame_stack < 1:
            raise ValueError(f"frame_stack must be a positive int (images per observation), got {cfg.frame_stack!r}")
        channels = 3 if cfg.tiled_camera.data_types == ["rgb"] else 1  # RGB, or one depth channel
        if not isinstance(cfg.observation_space, (gym.spaces.Dict, gym.spaces.Tuple, dict, tuple)):
            # the image alone (a Dict or Tuple space is a subclass's, the image one of its parts)
            cfg.observation_space = [cfg.tiled_camera.height, cfg.tiled_camera.width, channels * cfg.frame_stack]
        self._frames: torch.Tensor | None = None  # the last frame_stack images per env, (N, H, W, C * k)
        self._fresh: torch.Tensor | None = None  # envs reset since their last observation: history = now
        super().__init__(cfg, render_mode, **kwargs)
        if len(self.cfg.tiled_camera.data_types) != 1:
            raise ValueError(
                "The cartpole camera task observes one image type at a time, got"
                f" {self.cfg.tiled_camera.data_types}; use ['rgb'] or ['depth']"
            )

    def _setup_scene(self):
        self.cartpole = Articulation(self.cfg.robot_cfg)
        self._tiled_camera = TiledCamera(self.cfg.tiled_camera)
        self.scene.articulations["cartpole"] = self.cartpole
        self.scene.sensors["tiled_camera"] = self._tiled_camera
        light_cfg = sim_utils.DomeLightCfg(intensity=2000.0, color=(0.75, 0.75, 0.75))
        light_cfg.func("/World/Light", light_cfg)

    def _get_observations(self) -> dict:
        data_type = self.cfg.tiled_camera.data_types[0]
        image = self._tiled_camera.data.output[data_type]
        if data_type == "rgb":
            pixels = image / 255.0
            # each image minus its mean colour: the policy sees where things are, not the lighting
            pixels = pixels - pixels.mean(dim=(1, 2), keepdim=True)
        else:
            pixels = torch.where(torch.isinf(image), 0.0, image)
        if self.cfg.write_image_to_file:
            from simlab.sensors import save_images_to_file

            save_images_to_file(image, f"cartpole_{data_type}.png")
        return {"policy": self._stack(pixels)}

    def _stack(self, pixels: torch.Tensor) -> torch.Tensor:
        """The newest ``frame_stack`` images along the channel axis; an env just reset repeats its first."""
        if self.cfg.frame_stack == 1:
            return pixels
        self._history_buffers()
        shifted = torch.cat([self._frames[..., pixels.shape[-1] :], pixels], dim=-1)
        repeated = pixels.repeat(1, 1, 1, self.cfg.frame_stack)
        self._frames.copy_(torch.where(self._fresh.view(-1, 1, 1, 1), repeated, shifted))
        self._fresh.zero_()
        return self._frames.clone()

    def _history_buffers(self) -> None:
        if self._frames is None:
            height, width, channels = self.cfg.observation_space
            self._frames = torch.zeros(self.num_envs, height, width, channels, device=self.device)
            self._fresh = torch.ones(self.num_envs, dtype=torch.bool, device=self.device)

    def _reset_mask(self, env_mask: torch.Tensor):
        super()._reset_mask(env_mask)
        if self.cfg.frame_stack > 1:
            self._history_buffers()
            self._fresh |= env_mask
