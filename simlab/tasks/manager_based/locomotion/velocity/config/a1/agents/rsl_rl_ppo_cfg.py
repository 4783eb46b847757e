"""rsl_rl PPO for the A1 velocity tasks (Isaac Lab's published hyperparameters)."""

from simlab.utils import configclass

from ...common_ppo import VelocityRoughPPORunnerCfg, flat_runner


@configclass
class UnitreeA1RoughPPORunnerCfg(VelocityRoughPPORunnerCfg):
    experiment_name = "unitree_a1_rough"


@configclass
class UnitreeA1FlatPPORunnerCfg(UnitreeA1RoughPPORunnerCfg):
    def __post_init__(self):
        flat_runner(self, "unitree_a1_flat")
