"""rsl_rl PPO for the Go1 velocity tasks (Isaac Lab's published hyperparameters)."""

from simlab.utils import configclass

from ...common_ppo import VelocityRoughPPORunnerCfg, flat_runner


@configclass
class UnitreeGo1RoughPPORunnerCfg(VelocityRoughPPORunnerCfg):
    experiment_name = "unitree_go1_rough"


@configclass
class UnitreeGo1FlatPPORunnerCfg(UnitreeGo1RoughPPORunnerCfg):
    def __post_init__(self):
        flat_runner(self, "unitree_go1_flat", init_std=0.5)
