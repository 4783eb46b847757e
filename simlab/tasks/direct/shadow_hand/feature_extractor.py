"""The CNN of the Shadow Hand vision task (Isaac Lab's ``direct/shadow_hand/feature_extractor.py``): it
regresses the cube's position and its eight corners (27 values) from one camera's RGB, depth and
segmentation images, and is trained beside the policy, one Adam step per env step on that regression.

Isaac Lab's network: four stride-2 convolutions (16, 32, 64, 128 channels; kernels 6, 4, 4, 3) each with
ReLU and layer norm, a 6 x 6 average pool and a linear layer to 27, on 120 x 120 images of seven channels
(RGB, depth, segmentation RGB); the RGB and segmentation channels normalized with ImageNet's mean and
standard deviation (torchvision's ``Normalize``, written out here). The loss: mean squared error x 100.
Checkpoints are written every 50,000 steps (step 0 included) as ``cnn_<step>_<loss>.pth``, and the
Play variant loads the newest: Isaac Lab keeps them beside its source file, simlab under
``FeatureExtractorCfg.log_dir`` (the working directory's ``logs/shadow_hand_vision_cnn`` by default),
since an installed package's folder may not be writable.
"""

from __future__ import annotations

import glob
import os

import torch
from torch import nn

from simlab.utils import configclass
from simlab.utils.errors import CheckpointError, ConfigError, UntrustedFileError, describe
from simlab.utils.trust import torch_load

IMAGENET_MEAN = (0.485, 0.456, 0.406)
IMAGENET_STD = (0.229, 0.224, 0.225)
SAVE_EVERY = 50000
"""Steps between checkpoints, as Isaac Lab's."""


class FeatureExtractorNetwork(nn.Module):
    """Images (N, 120, 120, 7) -> (N, 27) the cube's position and corner keypoints."""

    def __init__(self):
        super().__init__()
        layers, channels, size = [], 7, 120
        for out, kernel in ((16, 6), (32, 4), (64, 4), (128, 3)):
            size = (size - kernel) // 2 + 1
            layers += [
                nn.Conv2d(channels, out, kernel_size=kernel, stride=2),
                nn.ReLU(),
                nn.LayerNorm([out, size, size]),
            ]
            channels = out
        self.cnn = nn.Sequential(*layers, nn.AvgPool2d(size))
        self.linear = nn.Sequential(nn.Linear(128, 27))
        self.register_buffer("mean", torch.tensor(IMAGENET_MEAN).view(1, 3, 1, 1))
        self.register_buffer("std", torch.tensor(IMAGENET_STD).view(1, 3, 1, 1))

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        x = x.permute(0, 3, 1, 2)
        rgb, depth, seg = x[:, 0:3], x[:, 3:4], x[:, 4:7]
        x = torch.cat(((rgb - self.mean) / self.std, depth, (seg - self.mean) / self.std), dim=1)
        return self.linear(self.cnn(x).flatten(1))


@configclass
class FeatureExtractorCfg:
    train: bool = True
    """Train the CNN during the rollouts (one step per env step)."""

    load_checkpoint: bool = False
    """Load the newest ``*.pth`` of ``log_dir`` at the start."""

    write_image_to_file: bool = False
    """Write the camera's images to PNG files each step (for a look)."""

    log_dir: str = os.path.join("logs", "shadow_hand_vision_cnn")
    """Where checkpoints are written and loaded from (simlab's field; relative to the working directory)."""


class FeatureExtractor:
    """The CNN, trained by ``step`` when ``cfg.train``, else only evaluated."""

    def __init__(self, cfg: FeatureExtractorCfg, device: str, log_dir: str | None = None):
        self.cfg = cfg
        self.device = device
        self.feature_extractor = FeatureExtractorNetwork().to(device)
        self.step_count = 0
        self.log_dir = log_dir or cfg.log_dir
        if cfg.load_checkpoint:
            checkpoints = glob.glob(os.path.join(self.log_dir, "*.pth"))
            if not checkpoints:
                raise ConfigError(
                    f"feature_extractor.load_checkpoint is set but {os.path.abspath(self.log_dir)} holds no CNN"
                    " checkpoint (*.pth; a relative log_dir is below the working folder); train the vision task"
                    " first (it writes them there) or point to them: env.feature_extractor.log_dir=<folder>"
                )
            newest = max(checkpoints, key=os.path.getctime)
            print(f"[INFO]: Loading feature extractor checkpoint from {newest}")
            self._load(newest)
        if cfg.train:
            self.optimizer = torch.optim.Adam(self.feature_extractor.parameters(), lr=1e-4)
            self.l2_loss = nn.MSELoss()
            self.feature_extractor.train()
        else:
            self.feature_extractor.eval()

    def _load(self, path: str) -> None:
        """The CNN's weights from ``path``, read as data (a file from elsewhere runs no code)."""
        allowed = "allowed: the tensors of FeatureExtractorNetwork's state dict, as the vision task's training writes"
        try:
            state = torch_load(path, map_location=self.device, what=f"the CNN checkpoint '{path}'", hint=allowed)
            self.feature_extractor.load_state_dict(state)
        except UntrustedFileError:
            raise
        except Exception as e:  # noqa: BLE001 - corrupt bytes make torch and pickle raise anything
            raise CheckpointError(f"Cannot load the CNN checkpoint '{path}' ({describe(e)}); {allowed}.") from None

    def _preprocess_images(
        self, rgb_img: torch.Tensor, depth_img: torch.Tensor, segmentation_img: torch.Tensor
    ) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor]:
        """RGB to [0, 1]; depth with misses as 0, over its batch maximum; segmentation to [0, 1] minus each
        image's mean (Isaac Lab's steps; its buffers are not written in place here)."""
        rgb_img = rgb_img / 255.0
        depth_img = torch.where(torch.isinf(depth_img), 0.0, depth_img) / 5.0
        depth_img = depth_img / depth_img.max().clamp_min(1e-6)
        segmentation_img = segmentation_img / 255.0
        segmentation_img = segmentation_img - segmentation_img.mean(dim=(1, 2), keepdim=True)
        return rgb_img, depth_img, segmentation_img

    def _save_images(self, rgb_img: torch.Tensor, depth_img: torch.Tensor, segmentation_img: torch.Tensor) -> None:
        from simlab.sensors import save_images_to_file

        save_images_to_file(rgb_img, "shadow_hand_rgb.png")
        save_images_to_file(depth_img, "shadow_hand_depth.png")
        save_images_to_file(segmentation_img, "shadow_hand_segmentation.png")

    def step(
        self, rgb_img: torch.Tensor, depth_img: torch.Tensor, segmentation_img: torch.Tensor, gt_pose: torch.Tensor
    ) -> tuple[torch.Tensor | None, torch.Tensor]:
        """(pose loss or None when not training, (N, 27) predicted pose) for images (N, H, W, 3 / 1 / 3)
        and the true pose (N, 27); one optimizer step when training."""
        rgb_img, depth_img, segmentation_img = self._preprocess_images(rgb_img, depth_img, segmentation_img)
        if self.cfg.write_image_to_file:
            self._save_images(rgb_img, depth_img, segmentation_img)
        img_input = torch.cat((rgb_img, depth_img, segmentation_img), dim=-1)
        if not self.cfg.train:
            with torch.no_grad():
                return None, self.feature_extractor(img_input)
        with torch.inference_mode(False), torch.enable_grad():
            self.optimizer.zero_grad()
            predicted_pose = self.feature_extractor(img_input.clone())
            pose_loss = self.l2_loss(predicted_pose, gt_pose.clone()) * 100
            pose_loss.backward()
            self.optimizer.step()
            if self.step_count % SAVE_EVERY == 0:
                os.makedirs(self.log_dir, exist_ok=True)
                name = f"cnn_{self.step_count}_{pose_loss.item()}.pth"
                torch.save(self.feature_extractor.state_dict(), os.path.join(self.log_dir, name))
            self.step_count += 1
            return pose_loss.detach(), predicted_pose
