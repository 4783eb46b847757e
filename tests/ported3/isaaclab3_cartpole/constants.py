# Copyright (c) 2022-2026, The Isaac Lab Project Developers (https://github.com/isaac-sim/IsaacLab/blob/main/CONTRIBUTORS.md).
# All rights reserved.
#
# SPDX-License-Identifier: BSD-3-Clause
#
# Isaac Lab 3.0's isaaclab_tasks/core/cartpole/constants.py; only the import differs (isaaclab.utils.math ->
# simlab.v3.utils.math, whose quat_from_euler_xyz returns (x, y, z, w) as 3.0's does).

import math

import torch

from simlab.v3.utils.math import quat_from_euler_xyz

CARTPOLE_DISTANT_LIGHT_INTENSITY: float = 2000.0
CARTPOLE_DISTANT_LIGHT_COLOR: tuple[float, float, float] = (1.0, 1.0, 1.0)
CARTPOLE_DISTANT_LIGHT_ORIENTATION: tuple[float, float, float, float] = tuple(
    quat_from_euler_xyz(
        torch.tensor([0.0]),
        torch.tensor([math.radians(-45.0)]),
        torch.tensor([math.radians(-45.0)]),
    )[0].tolist()
)
