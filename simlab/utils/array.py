"""Arrays of the different backends (NumPy, torch, Warp) and conversion to torch (Isaac Lab's ``utils.array``)."""

from __future__ import annotations

from typing import Any, Union

import numpy as np
import torch

try:  # Warp is optional (the gpu extra); without it only NumPy and torch arrays exist
    import warp as wp
except ImportError:  # pragma: no cover - depends on the install
    wp = None

__all__ = ["TENSOR_TYPES", "TENSOR_TYPE_CONVERSIONS", "TensorData", "convert_to_torch"]

TensorData = Union[np.ndarray, torch.Tensor] if wp is None else Union[np.ndarray, torch.Tensor, wp.array]  # noqa: UP007
"""A NumPy, torch or (when installed) Warp array."""

TENSOR_TYPES: dict[str, type] = {"numpy": np.ndarray, "torch": torch.Tensor}
"""The array type of each backend name."""

TENSOR_TYPE_CONVERSIONS: dict[str, dict[type, Any]] = {
    "numpy": {torch.Tensor: lambda x: x.detach().cpu().numpy()},
    "torch": {np.ndarray: lambda x: torch.from_numpy(x)},
}
"""``TENSOR_TYPE_CONVERSIONS[target][source_type](array)`` converts between backends."""

if wp is not None:
    TENSOR_TYPES["warp"] = wp.array
    TENSOR_TYPE_CONVERSIONS["numpy"][wp.array] = lambda x: x.numpy()
    TENSOR_TYPE_CONVERSIONS["torch"][wp.array] = lambda x: wp.to_torch(x)
    TENSOR_TYPE_CONVERSIONS["warp"] = {np.ndarray: lambda x: wp.array(x), torch.Tensor: lambda x: wp.from_torch(x)}


def convert_to_torch(
    array: Any, dtype: torch.dtype | None = None, device: torch.device | str | None = None
) -> torch.Tensor:
    """``array`` (torch, NumPy, Warp, list or tuple) as a torch tensor, on ``device`` and of ``dtype`` if given.

    Torch tensors and NumPy/Warp arrays share memory where they can; ``uint32`` becomes ``int32``
    (torch has no unsigned 32-bit type).
    """
    if isinstance(array, torch.Tensor):
        tensor = array
    elif isinstance(array, np.ndarray):
        tensor = torch.from_numpy(array.astype(np.int32) if array.dtype == np.uint32 else array)
    elif wp is not None and isinstance(array, wp.array):
        tensor = wp.to_torch(array.view(wp.int32) if array.dtype == wp.uint32 else array)
    else:
        tensor = torch.as_tensor(array, dtype=torch.float32 if dtype is None else dtype)
    if device is not None and str(tensor.device) != str(device):
        tensor = tensor.to(device)
    if dtype is not None and tensor.dtype != dtype:
        tensor = tensor.to(dtype)
    return tensor
