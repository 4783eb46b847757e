"""Isaac Lab's ``image_features`` observation term: a camera's images through a frozen encoder.

Models by ``model_name``:

* ``"simlab-cnn-random"``: simlab's own, here: three strided convolutions (16, 32, 64 channels) with
  ReLUs and a global average pool, 64 features per image. Its weights are drawn once from a fixed
  seed and never trained (random convolutional features: the same in every run and on every
  device), so it needs no download. A policy learns from these features, but they are not
  ImageNet features: for those use a ResNet.
* ``"resnet18"``, ``"resnet34"``, ``"resnet50"``, ``"resnet101"``: torchvision's ImageNet ResNets, as
  Isaac Lab runs them (torchvision downloads the weights on first use). They need torchvision.
* Isaac Lab's Theia names (``"theia-tiny-patch16-224-cddsv"``, ...): Hugging Face ``transformers``
  models that load remote code; simlab does not run them and says so.
* ``model_zoo_cfg={name: {"model": make, "inference": infer, "reset": reset}}``: your own, as in
  Isaac Lab (``make()`` returns the model, ``infer(model, images)`` the (N, D) features).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import torch

from simlab.managers import ManagerTermBase
from simlab.utils.errors import ConfigError

from .observations import _TILED_CAMERA, image

if TYPE_CHECKING:
    from simlab.envs import ManagerBasedEnv
    from simlab.managers import ObservationTermCfg, SceneEntityCfg

__all__ = ["image_features"]

SIMLAB_CNN = "simlab-cnn-random"
RESNETS = ("resnet18", "resnet34", "resnet50", "resnet101")
THEIA = (
    "theia-tiny-patch16-224-cddsv",
    "theia-tiny-patch16-224-cdiv",
    "theia-small-patch16-224-cdiv",
    "theia-base-patch16-224-cdiv",
    "theia-small-patch16-224-cddsv",
    "theia-base-patch16-224-cddsv",
)
_SEED = 0
_IMAGENET_MEAN = (0.485, 0.456, 0.406)
_IMAGENET_STD = (0.229, 0.224, 0.225)


class image_features(ManagerTermBase):  # noqa: N801 - Isaac Lab's name
    """Features (num_envs, D) of a camera's images from a frozen encoder (see the module docstring)."""

    def __init__(self, cfg: ObservationTermCfg, env: ManagerBasedEnv):
        super().__init__(cfg, env)
        zoo = cfg.params.get("model_zoo_cfg")
        name = cfg.params.get("model_name", "resnet18")
        device = cfg.params.get("model_device") or env.device
        if zoo is not None:
            if name not in zoo:
                raise ConfigError(f"image_features: model_name '{name}' is not in model_zoo_cfg ({list(zoo)}).")
            entry = zoo[name]
        elif name == SIMLAB_CNN:
            entry = {"model": lambda: None, "inference": _SimlabCNN(device)}
        elif name in RESNETS:
            entry = _resnet(name, device)
        elif name in THEIA:
            raise ConfigError(
                f"image_features: '{name}' is a Theia model that Isaac Lab loads from Hugging Face with its remote"
                f" code, which simlab does not run; use model_name='{SIMLAB_CNN}', a ResNet ({', '.join(RESNETS)}),"
                " or your own encoder through model_zoo_cfg."
            )
        else:
            raise ConfigError(
                f"image_features: unknown model_name '{name}'; simlab has '{SIMLAB_CNN}' and torchvision's"
                f" {', '.join(RESNETS)}, or give your own through model_zoo_cfg."
            )
        self._model = entry["model"]()
        self._reset_fn = entry.get("reset")
        self._inference_fn = entry["inference"]

    def reset(self, env_ids=None) -> None:
        if self._reset_fn is not None:
            self._reset_fn(self._model, env_ids)

    def __call__(
        self,
        env: ManagerBasedEnv,
        sensor_cfg: SceneEntityCfg = _TILED_CAMERA,
        data_type: str = "rgb",
        convert_perspective_to_orthogonal: bool = False,
        model_zoo_cfg: dict | None = None,
        model_name: str = "resnet18",
        model_device: str | None = None,
        inference_kwargs: dict | None = None,
    ) -> torch.Tensor:
        images = image(env, sensor_cfg, data_type, convert_perspective_to_orthogonal, normalize=False)
        with torch.no_grad():
            features = self._inference_fn(self._model, images, **(inference_kwargs or {}))
        return features.detach().to(images.device)


class _SimlabCNN:
    """``inference(None, images)``: the frozen seeded CNN, built for the images' channel count on first use."""

    def __init__(self, device: str):
        self._device = device
        self._net: torch.nn.Module | None = None

    def _build(self, channels: int) -> torch.nn.Module:
        generator = torch.Generator().manual_seed(_SEED)
        net = torch.nn.Sequential(
            torch.nn.Conv2d(channels, 16, 5, stride=2),
            torch.nn.ReLU(),
            torch.nn.Conv2d(16, 32, 3, stride=2),
            torch.nn.ReLU(),
            torch.nn.Conv2d(32, 64, 3, stride=2),
            torch.nn.ReLU(),
            torch.nn.AdaptiveAvgPool2d(1),
            torch.nn.Flatten(),
        )
        for layer in net:
            if isinstance(layer, torch.nn.Conv2d):  # drawn on the CPU from the seed: the same weights everywhere
                fan_in = layer.in_channels * layer.kernel_size[0] * layer.kernel_size[1]
                with torch.no_grad():
                    layer.weight.copy_(torch.randn(layer.weight.shape, generator=generator) * (2.0 / fan_in) ** 0.5)
                    layer.bias.zero_()
        return net.to(self._device).eval().requires_grad_(False)

    def __call__(self, model, images: torch.Tensor) -> torch.Tensor:
        if self._net is None:
            self._net = self._build(images.shape[-1])
        x = images.to(self._device).permute(0, 3, 1, 2).float()
        if x.shape[1] in (3, 4):  # RGB(A) in [0, 255]: to [-0.5, 0.5]
            x = x / 255.0 - 0.5
        x = torch.where(torch.isfinite(x), x, 0.0)  # depth where nothing is hit (inf): 0
        return self._net(x)


def _resnet(name: str, device: str) -> dict:
    try:
        from torchvision import models
    except ImportError as err:
        raise ConfigError(
            f"image_features: '{name}' is torchvision's ImageNet ResNet and torchvision is not installed ({err});"
            f" install it (pip install torchvision -c constraints.txt; its weights download on first use) or use"
            f" model_name='{SIMLAB_CNN}'."
        ) from err

    def load() -> torch.nn.Module:
        weights = {"resnet18": "ResNet18", "resnet34": "ResNet34", "resnet50": "ResNet50", "resnet101": "ResNet101"}
        return getattr(models, name)(weights=f"{weights[name]}_Weights.IMAGENET1K_V1").eval().to(device)

    mean = torch.tensor(_IMAGENET_MEAN, device=device).view(1, 3, 1, 1)
    std = torch.tensor(_IMAGENET_STD, device=device).view(1, 3, 1, 1)

    def infer(model, images: torch.Tensor) -> torch.Tensor:
        x = images.to(device).permute(0, 3, 1, 2).float() / 255.0
        return model((x - mean) / std)

    return {"model": load, "inference": infer}
