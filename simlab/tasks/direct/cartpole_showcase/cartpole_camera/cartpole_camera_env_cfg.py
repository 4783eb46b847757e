"""The camera showcase's configs (Isaac Lab's class names): the direct RGB camera cartpole with one pair
of spaces each.

Observations (``policy``): Box (100, 100, 3), the RGB image (the camera cartpole's: [0, 1] minus its
mean colour); Dict: ``joint-velocities`` (Box (2,): cart, pole) and ``camera`` (the image); Tuple:
(the image, the joint velocities). Actions: as the state showcase's (:mod:`..cartpole.cartpole_env_cfg`).
"""

from __future__ import annotations

from gymnasium import spaces

from simlab.tasks.direct.cartpole.cartpole_camera_env import CartpoleRGBCameraEnvCfg
from simlab.utils import configclass

from ..cartpole.cartpole_env_cfg import BOX_ACTION, DISCRETE_ACTION, MULTIDISCRETE_ACTION

_INF = float("inf")
IMAGE = spaces.Box(low=-_INF, high=_INF, shape=(100, 100, 3))  # the camera's height, width, RGB
JOINT_VELOCITIES = spaces.Box(low=-_INF, high=_INF, shape=(2,))
DICT_OBSERVATION = spaces.Dict({"joint-velocities": JOINT_VELOCITIES, "camera": IMAGE})
TUPLE_OBSERVATION = spaces.Tuple((IMAGE, JOINT_VELOCITIES))


@configclass
class BoxBoxEnvCfg(CartpoleRGBCameraEnvCfg):
    observation_space = IMAGE
    action_space = BOX_ACTION


@configclass
class BoxDiscreteEnvCfg(CartpoleRGBCameraEnvCfg):
    observation_space = IMAGE
    action_space = DISCRETE_ACTION


@configclass
class BoxMultiDiscreteEnvCfg(CartpoleRGBCameraEnvCfg):
    observation_space = IMAGE
    action_space = MULTIDISCRETE_ACTION


@configclass
class DictBoxEnvCfg(CartpoleRGBCameraEnvCfg):
    observation_space = DICT_OBSERVATION
    action_space = BOX_ACTION


@configclass
class DictDiscreteEnvCfg(CartpoleRGBCameraEnvCfg):
    observation_space = DICT_OBSERVATION
    action_space = DISCRETE_ACTION


@configclass
class DictMultiDiscreteEnvCfg(CartpoleRGBCameraEnvCfg):
    observation_space = DICT_OBSERVATION
    action_space = MULTIDISCRETE_ACTION


@configclass
class TupleBoxEnvCfg(CartpoleRGBCameraEnvCfg):
    observation_space = TUPLE_OBSERVATION
    action_space = BOX_ACTION


@configclass
class TupleDiscreteEnvCfg(CartpoleRGBCameraEnvCfg):
    observation_space = TUPLE_OBSERVATION
    action_space = DISCRETE_ACTION


@configclass
class TupleMultiDiscreteEnvCfg(CartpoleRGBCameraEnvCfg):
    observation_space = TUPLE_OBSERVATION
    action_space = MULTIDISCRETE_ACTION
