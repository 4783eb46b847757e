"""Optional libraries: import one, or fail with one line naming its pip install.

In the lowest layer, so that any module (a sensor saving images, a library wrapper) can say how to
install what it needs.
"""

from __future__ import annotations

import importlib
from types import ModuleType

from simlab.utils.errors import MissingDependencyError

__all__ = ["require"]

# library module -> (pip distribution, simlab extra)
_LIBRARIES = {
    "rsl_rl": ("rsl-rl-lib", "rsl_rl"),
    "tensordict": ("tensordict", "rsl_rl"),
    "skrl": ("skrl", "skrl"),
    "stable_baselines3": ("stable-baselines3", "sb3"),
    "rl_games": ("rl-games", "rl_games"),
    "onnx": ("onnx", "train"),
    "onnxruntime": ("onnxruntime", "train"),
    "tensorboard": ("tensorboard", "train"),
    "tqdm": ("tqdm", "train"),
    "rich": ("rich", "sb3"),
    "imageio": ("imageio", "render"),
    "imageio_ffmpeg": ("imageio-ffmpeg", "render"),
    "moviepy": ("moviepy", "render"),
}


def require(module: str) -> ModuleType:
    """Import ``module``, or raise a ``MissingDependencyError`` (an ``ImportError``) naming its pip install."""
    try:
        return importlib.import_module(module)
    except ImportError as e:
        top = module.split(".")[0]
        dist, extra = _LIBRARIES.get(top, (top, "all"))
        raise MissingDependencyError(
            f"This feature needs the '{dist}' library, which is not installed ({e}). "
            f'Install it with: pip install "simlab[{extra}]"'
        ) from e
