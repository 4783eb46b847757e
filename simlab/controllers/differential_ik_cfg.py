"""Configuration of the differential inverse-kinematics controller (Isaac Lab's fields and defaults)."""

from __future__ import annotations

from dataclasses import MISSING
from typing import Literal

from simlab.utils import configclass

from .differential_ik import DifferentialIKController

IK_METHODS = ("pinv", "svd", "trans", "dls")
COMMAND_TYPES = ("position", "pose")
_DEFAULT_IK_PARAMS = {
    "pinv": {"k_val": 1.0},
    "svd": {"k_val": 1.0, "min_singular_value": 1e-5},
    "trans": {"k_val": 1.0},
    "dls": {"lambda_val": 0.01},
}


@configclass
class DifferentialIKControllerCfg:
    class_type: type = DifferentialIKController

    command_type: Literal["position", "pose"] = MISSING
    """``"position"``: the body's position only; ``"pose"``: position and orientation."""
    use_relative_mode: bool = False
    """Commands are changes of the current position / pose instead of absolute targets."""
    ik_method: Literal["pinv", "svd", "trans", "dls"] = MISSING
    """How the Jacobian is inverted: pseudo-inverse, truncated SVD, transpose, damped least squares."""
    ik_params: dict[str, float] | None = None
    """``pinv``/``trans``: ``k_val`` (gain, 1.0); ``svd``: ``k_val``, ``min_singular_value`` (1e-5);
    ``dls``: ``lambda_val`` (damping, 0.01). Missing entries take these defaults."""

    def __post_init__(self):
        if self.command_type is not MISSING and self.command_type not in COMMAND_TYPES:
            raise ValueError(
                f"Unsupported inverse-kinematics command_type {self.command_type!r}; use one of {COMMAND_TYPES}"
            )
        if self.ik_method is not MISSING:
            if self.ik_method not in IK_METHODS:
                raise ValueError(
                    f"Unsupported inverse-kinematics ik_method {self.ik_method!r}; use one of {IK_METHODS}"
                )
            params = dict(_DEFAULT_IK_PARAMS[self.ik_method])
            unknown = set(self.ik_params or {}) - set(params)
            if unknown:
                raise ValueError(
                    f"ik_params {sorted(unknown)} do not apply to ik_method {self.ik_method!r};"
                    f" it takes {sorted(params)}"
                )
            params.update(self.ik_params or {})
            self.ik_params = params
