"""The stack task's behaviour cloning (Isaac Lab registers robomimic's BC for it): the recipe of
``scripts/imitation_learning/bc.py train`` that stacked the cubes from the state machine's
demonstrations (docs/manipulation.md)."""

from simlab.rl.bc import BCAgentCfg
from simlab.utils import configclass


@configclass
class StackCubeBCCfg(BCAgentCfg):
    experiment_name: str = "franka_stack"
