"""Robot configurations and their MJCF models (``simlab.robots.<robot>``)."""

from .agility import DIGIT_V4_CFG
from .allegro import ALLEGRO_HAND_CFG
from .ant import ANT_CFG
from .anymal import ANYMAL_B_CFG, ANYMAL_C_CFG, ANYMAL_D_CFG
from .cabinet import SEKTION_CABINET_CFG
from .cart_double_pendulum import CART_DOUBLE_PENDULUM_CFG
from .cartpole import CARTPOLE_CFG
from .cassie import CASSIE_CFG
from .flexiv import FLEXIV_RIZON4S_CFG
from .franka import FRANKA_PANDA_CFG, FRANKA_PANDA_HIGH_PD_CFG
from .humanoid import HUMANOID_CFG
from .humanoid_28 import HUMANOID_28_CFG
from .openarm import OPENARM_BI_CFG, OPENARM_BI_HIGH_PD_CFG, OPENARM_UNI_CFG, OPENARM_UNI_HIGH_PD_CFG
from .quadcopter import CRAZYFLIE_CFG
from .shadow_hand import SHADOW_HAND_CFG
from .unitree import (
    G1_29DOF_CFG,
    G1_CFG,
    G1_MINIMAL_CFG,
    H1_CFG,
    H1_MINIMAL_CFG,
    UNITREE_A1_CFG,
    UNITREE_GO1_CFG,
    UNITREE_GO2_CFG,
)
from .universal_robots import UR10_CFG, UR10e_CFG
