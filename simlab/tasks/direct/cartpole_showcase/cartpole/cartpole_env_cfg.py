"""The showcase's configs (Isaac Lab's class names): the direct cartpole with one pair of spaces each.

Observations (``policy``):

- Box (4,): pole angle, pole velocity, cart position, cart velocity (the direct cartpole's);
- Discrete(16): the signs of pole angle, cart position, pole velocity, cart velocity as the bits of
  a number, most significant first, 1 for >= 0 (0: all negative, 8: only the pole angle >= 0);
- MultiDiscrete([2, 2, 2, 2]): the same four signs, one per entry;
- Dict: ``joint-positions`` and ``joint-velocities``, Box (2,) each (cart, pole);
- Tuple: (joint positions, joint velocities).

Actions (the force on the cart, ``action_scale`` = 100 N at most):

- Box (1,) in [-1, 1]: a fraction of the largest force;
- Discrete(3): 0 no force, 1 full force backwards (-x), 2 full force forwards;
- MultiDiscrete([3, 2]): a size (0, half, full) and a direction (0 backwards, 1 forwards).
"""

from __future__ import annotations

from gymnasium import spaces

from simlab.tasks.direct.cartpole.cartpole_env import CartpoleEnvCfg
from simlab.utils import configclass

_INF = float("inf")
BOX_OBSERVATION = spaces.Box(low=-_INF, high=_INF, shape=(4,))
DISCRETE_OBSERVATION = spaces.Discrete(16)
MULTIDISCRETE_OBSERVATION = spaces.MultiDiscrete([2, 2, 2, 2])
DICT_OBSERVATION = spaces.Dict(
    {
        "joint-positions": spaces.Box(low=-_INF, high=_INF, shape=(2,)),
        "joint-velocities": spaces.Box(low=-_INF, high=_INF, shape=(2,)),
    }
)
TUPLE_OBSERVATION = spaces.Tuple((spaces.Box(low=-_INF, high=_INF, shape=(2,)), spaces.Box(-_INF, _INF, shape=(2,))))

BOX_ACTION = spaces.Box(low=-1.0, high=1.0, shape=(1,))
DISCRETE_ACTION = spaces.Discrete(3)
MULTIDISCRETE_ACTION = spaces.MultiDiscrete([3, 2])


@configclass
class BoxBoxEnvCfg(CartpoleEnvCfg):
    observation_space = BOX_OBSERVATION
    action_space = BOX_ACTION


@configclass
class BoxDiscreteEnvCfg(CartpoleEnvCfg):
    observation_space = BOX_OBSERVATION
    action_space = DISCRETE_ACTION


@configclass
class BoxMultiDiscreteEnvCfg(CartpoleEnvCfg):
    observation_space = BOX_OBSERVATION
    action_space = MULTIDISCRETE_ACTION


@configclass
class DiscreteBoxEnvCfg(CartpoleEnvCfg):
    observation_space = DISCRETE_OBSERVATION
    action_space = BOX_ACTION


@configclass
class DiscreteDiscreteEnvCfg(CartpoleEnvCfg):
    observation_space = DISCRETE_OBSERVATION
    action_space = DISCRETE_ACTION


@configclass
class DiscreteMultiDiscreteEnvCfg(CartpoleEnvCfg):
    observation_space = DISCRETE_OBSERVATION
    action_space = MULTIDISCRETE_ACTION


@configclass
class MultiDiscreteBoxEnvCfg(CartpoleEnvCfg):
    observation_space = MULTIDISCRETE_OBSERVATION
    action_space = BOX_ACTION


@configclass
class MultiDiscreteDiscreteEnvCfg(CartpoleEnvCfg):
    observation_space = MULTIDISCRETE_OBSERVATION
    action_space = DISCRETE_ACTION


@configclass
class MultiDiscreteMultiDiscreteEnvCfg(CartpoleEnvCfg):
    observation_space = MULTIDISCRETE_OBSERVATION
    action_space = MULTIDISCRETE_ACTION


@configclass
class DictBoxEnvCfg(CartpoleEnvCfg):
    observation_space = DICT_OBSERVATION
    action_space = BOX_ACTION


@configclass
class DictDiscreteEnvCfg(CartpoleEnvCfg):
    observation_space = DICT_OBSERVATION
    action_space = DISCRETE_ACTION


@configclass
class DictMultiDiscreteEnvCfg(CartpoleEnvCfg):
    observation_space = DICT_OBSERVATION
    action_space = MULTIDISCRETE_ACTION


@configclass
class TupleBoxEnvCfg(CartpoleEnvCfg):
    observation_space = TUPLE_OBSERVATION
    action_space = BOX_ACTION


@configclass
class TupleDiscreteEnvCfg(CartpoleEnvCfg):
    observation_space = TUPLE_OBSERVATION
    action_space = DISCRETE_ACTION


@configclass
class TupleMultiDiscreteEnvCfg(CartpoleEnvCfg):
    observation_space = TUPLE_OBSERVATION
    action_space = MULTIDISCRETE_ACTION
