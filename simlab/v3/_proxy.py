"""Asset data as Isaac Lab 3.0 code reads it, on the same tensors 2.x code reads.

Isaac Lab 3.0's data properties return a ``ProxyArray``: ``.torch`` is the tensor, ``.warp`` the Warp
array, and quaternions are ``(x, y, z, w)``. simlab's data are tensors in ``(w, x, y, z)``, and 2.x code
(simlab's own terms among it) reads them as such. A :class:`ProxyTensor` is both: it *is* simlab's
tensor (same storage, same ``(w, x, y, z)`` values, every torch operation on it gives a plain tensor),
and its ``.torch`` / ``.warp`` are what 3.0 code asks for. So the order is chosen by the accessor, never
guessed: ``data.root_quat_w`` is 2.x's ``(w, x, y, z)``, ``data.root_quat_w.torch`` is 3.0's
``(x, y, z, w)``. Where 3.0 code hands a proxy back to simlab without ``.torch`` (a writer, a function
of :mod:`simlab.v3.utils.math`), :func:`as_v3` reads it as 3.0 would.
"""

from __future__ import annotations

import copy
from typing import Any

import torch

__all__ = ["ProxyTensor", "QuatProxyTensor", "as_v3", "proxy", "quat_column"]


def _xyzw(quat: torch.Tensor) -> torch.Tensor:
    return torch.roll(quat, -1, dims=-1)


class ProxyTensor(torch.Tensor):
    """simlab's data tensor (2.x order) with Isaac Lab 3.0's ``.torch`` and ``.warp`` accessors."""

    # Operations on a proxy give plain tensors: the proxy never spreads into observations or buffers.
    __torch_function__ = torch._C._disabled_torch_function_impl

    def _as_torch(self) -> torch.Tensor:
        """The values in Isaac Lab 3.0's order (the same storage: there are no quaternions here)."""
        return self.as_subclass(torch.Tensor)

    def _as_warp(self) -> Any:
        import warp as wp

        wp.init()  # once per process; Warp's arrays need its runtime
        return wp.from_torch(self._as_torch().contiguous())

    def __deepcopy__(self, memo: dict) -> torch.Tensor:
        return copy.deepcopy(self.as_subclass(torch.Tensor), memo)

    def __reduce_ex__(self, protocol: int) -> Any:
        return self.as_subclass(torch.Tensor).__reduce_ex__(protocol)

    torch = property(_as_torch, doc="Isaac Lab 3.0's ``ProxyArray.torch``: the values as a tensor.")
    warp = property(_as_warp, doc="Isaac Lab 3.0's ``ProxyArray.warp``: the values as a Warp array.")


class QuatProxyTensor(ProxyTensor):
    """A data tensor holding a quaternion at columns ``quat_at:quat_at + 4`` of its last dimension:
    ``(w, x, y, z)`` as a tensor, ``(x, y, z, w)`` through ``.torch`` (a copy: the order differs)."""

    quat_at: int = 0

    def _as_torch(self) -> torch.Tensor:
        values = self.as_subclass(torch.Tensor)
        at = self.quat_at
        if at == 0 and values.shape[-1] == 4:
            return _xyzw(values)
        return torch.cat([values[..., :at], _xyzw(values[..., at : at + 4]), values[..., at + 4 :]], dim=-1)

    torch = property(_as_torch, doc="The values with the quaternion in (x, y, z, w) order, Isaac Lab 3.0's.")


# width of the last dimension -> where the quaternion starts: a quaternion, a pose (pos, quat), a
# state (pos, quat, lin_vel, ang_vel)
_QUAT_AT = {4: 0, 7: 3, 13: 3}


def quat_column(name: str, value: torch.Tensor) -> int | None:
    """Where a data field's quaternion starts in its last dimension, None if it holds none.

    By Isaac Lab's naming, which 2.x and 3.0 share: ``*quat*`` fields are quaternions, ``*_pose*``
    fields (position, quaternion) and the root and body ``*_state*`` fields (position, quaternion,
    velocities). A field so named whose width does not fit is refused rather than read in a guessed order.
    """
    if "quat" in name:
        width = 4
    elif "_pose" in name or "root_state" in name or "body_state" in name or "link_state" in name or "com_state" in name:
        width = value.shape[-1] if value.shape[-1] in (7, 13) else -1
    else:
        return None
    if value.shape[-1] != width or width not in _QUAT_AT:
        raise RuntimeError(
            f"data.{name} has shape {tuple(value.shape)}; simlab expected a quaternion (4), pose (7) or state (13) "
            "in its last dimension and cannot tell where its quaternion is"
        )
    return _QUAT_AT[width]


def proxy(name: str, value: Any) -> Any:
    """``value`` (a data field named ``name``) as Isaac Lab 3.0 code reads it; non-tensors as they are."""
    if not isinstance(value, torch.Tensor) or isinstance(value, ProxyTensor):
        return value
    at = quat_column(name, value)
    if at is None:
        return value.as_subclass(ProxyTensor)
    out = value.as_subclass(QuatProxyTensor)
    out.quat_at = at
    return out


def as_v3(value: Any) -> Any:
    """A value that 3.0 code passes to simlab, in 3.0's order: a proxy read through ``.torch`` (3.0's
    deprecated bridge lets its code skip ``.torch``), a Warp array as a tensor, anything else as it is."""
    if isinstance(value, ProxyTensor):
        return value.torch
    if type(value).__module__.startswith("warp"):
        import warp as wp

        return wp.to_torch(value)
    return value
