"""Shadow Hand cube reorientation from a camera (Isaac Lab's ``direct/shadow_hand/shadow_hand_vision_env.py``).

The direct Shadow Hand task ("full" settings) with a 120 x 120 camera 1 m above each env looking down
at the hand (RGB, depth and segmentation). A small CNN (:mod:`.feature_extractor`) trained beside the
policy regresses the cube's position and eight corners from the images; the policy sees no cube
state, only the hand's (joint positions and velocities, the in-hand position, the goal orientation,
the fingertips' poses and velocities, its last actions: 140 values) and the CNN's 27 features with the
goal cube's corners (24): 191 values. The critic gets the full state with the fingertips' wrenches
(187) and the CNN's features: 214. The goal cube is moved out of the camera's view, and the CNN's
loss is logged as ``pose_loss``.

Differences from Isaac Lab's file: MuJoCo models have no semantic labels, so the segmentation image
is made from the camera's body ids: the cube's pixels white, the rest black, where Isaac Lab labels
the cube alone ("class: cube") and colours it. The CNN trains inside the env step (an optimizer step
and a host read for its checkpoints), so the step runs eagerly, never as a CUDA graph.
"""

from __future__ import annotations

import torch

import simlab.sim as sim_utils
from simlab.assets import Articulation, RigidObject
from simlab.scene import InteractiveSceneCfg
from simlab.sensors import TiledCamera, TiledCameraCfg
from simlab.sim.spawners.from_files import GroundPlaneCfg, spawn_ground_plane
from simlab.tasks.direct.inhand_manipulation.inhand_manipulation_env import InHandManipulationEnv, unscale
from simlab.utils import configclass
from simlab.utils.math import quat_apply

from .feature_extractor import FeatureExtractor, FeatureExtractorCfg
from .shadow_hand_env_cfg import ShadowHandEnvCfg

HIDDEN_GOAL_POS = (-0.2, 0.1, 0.6)
"""Where the goal cube is drawn (env frame): outside the camera's view, as Isaac Lab's."""


@configclass
class ShadowHandVisionEnvCfg(ShadowHandEnvCfg):
    # scene
    scene: InteractiveSceneCfg = InteractiveSceneCfg(num_envs=1225, env_spacing=2.0, replicate_physics=True)

    # camera: 1 m above the env, looking down (world convention: forward +x turned to -z)
    tiled_camera: TiledCameraCfg = TiledCameraCfg(
        prim_path="/World/envs/env_.*/Camera",
        offset=TiledCameraCfg.OffsetCfg(pos=(0, -0.35, 1.0), rot=(0.7071, 0.0, 0.7071, 0.0), convention="world"),
        data_types=["rgb", "depth", "semantic_segmentation"],
        spawn=sim_utils.PinholeCameraCfg(
            focal_length=24.0, focus_distance=400.0, horizontal_aperture=20.955, clipping_range=(0.1, 20.0)
        ),
        width=120,
        height=120,
        colorize_semantic_segmentation=False,  # body ids: the env makes the cube's mask from them
    )
    feature_extractor: FeatureExtractorCfg = FeatureExtractorCfg()

    # env
    observation_space = 164 + 27  # state observation + vision CNN embedding
    state_space = 187 + 27  # asymmetric states + vision CNN embedding


@configclass
class ShadowHandVisionEnvPlayCfg(ShadowHandVisionEnvCfg):
    scene: InteractiveSceneCfg = InteractiveSceneCfg(num_envs=64, env_spacing=2.0, replicate_physics=True)
    # the CNN evaluated, from the newest checkpoint training wrote
    feature_extractor: FeatureExtractorCfg = FeatureExtractorCfg(train=False, load_checkpoint=True)


class ShadowHandVisionEnv(InHandManipulationEnv):
    cfg: ShadowHandVisionEnvCfg

    def __init__(self, cfg: ShadowHandVisionEnvCfg, render_mode: str | None = None, **kwargs):
        super().__init__(cfg, render_mode, **kwargs)
        self.feature_extractor = FeatureExtractor(self.cfg.feature_extractor, self.device)
        self.goal_pos[:] = torch.tensor(HIDDEN_GOAL_POS, device=self.device)
        self.gt_keypoints = torch.ones(self.num_envs, 8, 3, dtype=torch.float32, device=self.device)
        self.goal_keypoints = torch.ones(self.num_envs, 8, 3, dtype=torch.float32, device=self.device)
        self.embeddings = torch.zeros(self.num_envs, 27, device=self.device)

    def _setup_scene(self):
        self.hand = Articulation(self.cfg.robot_cfg)
        self.object = RigidObject(self.cfg.object_cfg)
        self._tiled_camera = TiledCamera(self.cfg.tiled_camera)
        spawn_ground_plane(prim_path="/World/ground", cfg=GroundPlaneCfg())
        self.scene.clone_environments(copy_from_source=False)
        self.scene.articulations["robot"] = self.hand
        self.scene.rigid_objects["object"] = self.object
        self.scene.sensors["tiled_camera"] = self._tiled_camera
        # the critic reads the fingertips' incoming joint wrenches (cfrc_int)
        sim_utils.compute_body_interaction_forces(self.sim.spec)
        light_cfg = sim_utils.DomeLightCfg(intensity=2000.0, color=(0.75, 0.75, 0.75))
        light_cfg.func("/World/Light", light_cfg)

    def graph_blockers(self) -> list[str]:
        blockers = super().graph_blockers()
        if self.cfg.feature_extractor.train:
            blockers.append("the vision task trains its CNN inside the step (an optimizer step, checkpoints)")
        return blockers

    def _segmentation_rgb(self) -> torch.Tensor:
        """(N, H, W, 3) uint8: the cube's pixels 255, the rest 0 (from the camera's body ids)."""
        ids = self._tiled_camera.data.output["semantic_segmentation"]
        cube = (ids == self.object._root_body).to(torch.uint8) * 255
        return cube.expand(-1, -1, -1, 3)

    def _compute_image_observations(self) -> torch.Tensor:
        compute_keypoints(torch.cat((self.object_pos, self.object_rot), dim=1), out=self.gt_keypoints)
        object_pose = torch.cat([self.object_pos, self.gt_keypoints.view(-1, 24)], dim=-1)
        output = self._tiled_camera.data.output
        pose_loss, embeddings = self.feature_extractor.step(
            output["rgb"], output["depth"], self._segmentation_rgb(), object_pose
        )
        self.embeddings = embeddings.clone().detach()
        compute_keypoints(torch.cat((torch.zeros_like(self.goal_pos), self.goal_rot), dim=-1), out=self.goal_keypoints)
        if pose_loss is not None:
            self.extras.setdefault("log", {})["pose_loss"] = pose_loss
        return torch.cat((self.embeddings, self.goal_keypoints.view(-1, 24)), dim=-1)

    def _compute_proprio_observations(self) -> torch.Tensor:
        n, tips = self.num_envs, self.num_fingertips
        return torch.cat(
            (
                unscale(self.hand_dof_pos, self.hand_dof_lower_limits, self.hand_dof_upper_limits),
                self.cfg.vel_obs_scale * self.hand_dof_vel,
                self.in_hand_pos,
                self.goal_rot,
                self.fingertip_pos.reshape(n, tips * 3),
                self.fingertip_rot.reshape(n, tips * 4),
                self.fingertip_velocities.reshape(n, tips * 6),
                self.actions,
            ),
            dim=-1,
        )

    def _compute_states(self) -> torch.Tensor:
        return torch.cat((self.compute_full_state(), self.embeddings), dim=-1)

    def _get_observations(self) -> dict:
        self._compute_intermediate_values()
        obs = torch.cat((self._compute_proprio_observations(), self._compute_image_observations()), dim=-1)
        self.fingertip_force_sensors = self.hand.data.body_incoming_joint_wrench_b[:, self._tips]
        return {"policy": obs, "critic": self._compute_states()}


def compute_keypoints(
    pose: torch.Tensor,
    num_keypoints: int = 8,
    size: tuple[float, float, float] = (2 * 0.03, 2 * 0.03, 2 * 0.03),
    out: torch.Tensor | None = None,
) -> torch.Tensor:
    """(N, 8, 3) the corners of a cube of edges ``size`` [m] at ``pose`` (N, 7: position, quaternion w-x-y-z):
    corner i is at +-size/2 on each axis, minus where bit k of i is set (Isaac Lab's order)."""
    n = pose.shape[0]
    if out is None:
        out = torch.empty(n, num_keypoints, 3, dtype=torch.float32, device=pose.device)
    signs = torch.tensor(
        [[-1.0 if (i >> k) & 1 else 1.0 for k in range(3)] for i in range(num_keypoints)], device=pose.device
    )
    corners = signs * torch.tensor(size, device=pose.device) / 2  # (8, 3) in the cube's frame
    quat = pose[:, None, 3:7].expand(n, num_keypoints, 4)
    out[:] = pose[:, None, :3] + quat_apply(quat.reshape(-1, 4), corners.repeat(n, 1)).view(n, num_keypoints, 3)
    return out
