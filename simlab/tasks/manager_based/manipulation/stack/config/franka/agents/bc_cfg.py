"""The stack task's behaviour cloning (Isaac Lab registers robomimic's BC for it): the recipe of
``scripts/imitation_learning/bc.py train`` that stacked the cubes from the state machine's
demonstrations (docs/manipulation.md)."""

from simlab.rl.bc import BCAgentCfg
from simlab.utils import configclass


@configclass
class StackCubeBCCfg(BCAgentCfg):
    experiment_name: str = "franka_stack"


@configclass
class StackCubeIKRelBCCfg(BCAgentCfg):
    """The IK-Rel tasks' recipe: their actions are already deltas from the end effector, so none is
    predicted as an offset from an observation."""

    experiment_name: str = "franka_stack_ik_rel"
    relative: int = 0
