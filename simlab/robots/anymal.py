"""ANYbotics robots (Isaac Lab's ``isaaclab_assets.robots.anymal``): ANYmal-B, ANYmal-C and ANYmal-D."""

import os

import simlab.sim as sim_utils
from simlab.actuators import ActuatorNetLSTMCfg, DCMotorCfg
from simlab.assets import ArticulationCfg
from simlab.utils.assets import ISAACLAB_NUCLEUS_DIR

ASSETS_DIR = os.path.join(os.path.dirname(__file__), "assets")

ANYDRIVE_3_SIMPLE_ACTUATOR_CFG = DCMotorCfg(
    joint_names_expr=[".*HAA", ".*HFE", ".*KFE"],
    saturation_effort=120.0,
    effort_limit=80.0,
    velocity_limit=7.5,
    stiffness={".*": 40.0},
    damping={".*": 5.0},
)
"""ANYdrive 3.x as a DC motor (Isaac Lab's simple actuator model, its numbers). Too soft to hold
ANYmal-C in its default pose: see ``ANYDRIVE_3_STIFF_ACTUATOR_CFG``."""

ANYDRIVE_3_STIFF_ACTUATOR_CFG = ANYDRIVE_3_SIMPLE_ACTUATOR_CFG.replace(stiffness={".*": 200.0}, damping={".*": 11.0})
"""simlab's DC-motor stand-in for Isaac Lab's ``ANYDRIVE_3_LSTM_ACTUATOR_CFG`` (whose network Isaac Lab
trained on the real drives; simlab's network of that name is fitted to this motor): the same DC-motor
limits (80 N m, 120 N m saturation, 7.5 rad/s), with a stiffness that holds the robot as the real
drives do and a damping that keeps the simple model's damping ratio.

In the default pose each HAA, HFE and KFE carries about 22 N m (a quarter of the 45 kg on a lever of
about 0.2 m: the feet stand 0.2 m outboard of the HAA axes and 0.2 m ahead of or behind the knees).
Measured in simlab (flat ground, PD targets at the default pose, base height after 3 s; it stands
at 0.55 m with rigid joints): kp 40 (Isaac Lab's simple model) 0.21 m, the robot folds onto its
knees; kp 80 (legged_gym's ANYmal-C PD gains) 0.26 m; kp 200 0.47 m, joints within 0.14 rad of
their targets. The stiffness is simlab's choice, not a published figure.

Damping 11 N m s/rad rather than 5: with the joints' armature (0.05 kg m^2) the simple model's kp 40 /
kd 5 has a damping ratio of 1.8; kp 200 with kd 5 would have 0.8, and kd 11 has 1.7. Flat-ground
policies trained with kd 5 levelled off at a velocity error of 0.22-0.26 m/s (their bases swaying
within each step); with kd 11, 0.116 m/s after 250 iterations (docs/locomotion.md)."""

ANYDRIVE_3_LSTM_ACTUATOR_CFG = ActuatorNetLSTMCfg(
    joint_names_expr=[".*HAA", ".*HFE", ".*KFE"],
    network_file=f"{ISAACLAB_NUCLEUS_DIR}/ActuatorNets/ANYbotics/anydrive_3_lstm_jit.pt",
    saturation_effort=120.0,
    effort_limit=80.0,
    velocity_limit=7.5,
)
"""Isaac Lab's ANYdrive 3.0 LSTM actuator config (its limits). Its network path names simlab's
``simlab/actuators/nets/anydrive_3_lstm.pt``: an LSTM fitted here to ``ANYDRIVE_3_STIFF_ACTUATOR_CFG``
receiving its targets 2 physics steps late (docs/actuators.md), not the network ANYbotics trained on
the real drives.
ANYmal-B and ANYmal-D use it; ANYmal-C keeps the DC-motor drive its shipped policies were trained with."""


ANYMAL_C_CFG = ArticulationCfg(
    spawn=sim_utils.MjcfFileCfg(
        asset_path=os.path.join(ASSETS_DIR, "anybotics_anymal_c.xml"),
        # PhysX's solver settings, as Isaac Lab's config has them (MuJoCo's solver is sim.mujoco)
        articulation_props=sim_utils.ArticulationRootPropertiesCfg(
            solver_position_iteration_count=4, solver_velocity_iteration_count=0
        ),
    ),
    init_state=ArticulationCfg.InitialStateCfg(
        pos=(0.0, 0.0, 0.6),
        joint_pos={
            ".*HAA": 0.0,
            ".*F_HFE": 0.4,
            ".*H_HFE": -0.4,
            ".*F_KFE": -0.8,
            ".*H_KFE": 0.8,
        },
    ),
    actuators={"legs": ANYDRIVE_3_STIFF_ACTUATOR_CFG},
    soft_joint_pos_limit_factor=0.95,
)
"""ANYmal-C. Isaac Lab drives it with its LSTM actuator network of the real drives
(``ANYDRIVE_3_LSTM_ACTUATOR_CFG``); here the stiffer DC-motor ANYdrive (``ANYDRIVE_3_STIFF_ACTUATOR_CFG``)
that holds the robot in its default pose, which simlab's shipped ANYmal-C policies were trained with.
simlab's network of that config name is an LSTM fitted to this DC motor with a 2-step command latency
(ANYmal-B and -D use it); ``ANYMAL_C_CFG.replace(actuators={"legs": ANYDRIVE_3_LSTM_ACTUATOR_CFG})``
drives ANYmal-C with it."""


ANYMAL_B_CFG = ANYMAL_C_CFG.replace(
    spawn=ANYMAL_C_CFG.spawn.replace(asset_path=os.path.join(ASSETS_DIR, "anybotics_anymal_b.xml")),
    actuators={"legs": ANYDRIVE_3_LSTM_ACTUATOR_CFG},
)
"""ANYmal-B (30.4 kg) with ANYmal-C's pose and spawn height, driven as Isaac Lab drives it by the ANYdrive
LSTM actuator network config (simlab's network: the stiff DC-motor ANYdrive with a 2-step command latency)."""

ANYMAL_D_CFG = ANYMAL_C_CFG.replace(
    spawn=ANYMAL_C_CFG.spawn.replace(asset_path=os.path.join(ASSETS_DIR, "anybotics_anymal_d.xml")),
    actuators={"legs": ANYDRIVE_3_LSTM_ACTUATOR_CFG},
)
"""ANYmal-D (51.5 kg) with ANYmal-C's pose and spawn height, driven as Isaac Lab drives it by ANYmal-C's
ANYdrive LSTM actuator network config (Isaac Lab has no network of ANYmal-D's drives either; simlab's
network: the stiff DC-motor ANYdrive with a 2-step command latency)."""
