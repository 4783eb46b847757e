"""rsl_rl PPO for the Go2 velocity tasks (Isaac Lab's published hyperparameters)."""

from simlab.utils import configclass

from ...common_ppo import VelocityRoughPPORunnerCfg, flat_runner


@configclass
class UnitreeGo2RoughPPORunnerCfg(VelocityRoughPPORunnerCfg):
    experiment_name = "unitree_go2_rough"


@configclass
class UnitreeGo2FlatPPORunnerCfg(UnitreeGo2RoughPPORunnerCfg):
    def __post_init__(self):
        flat_runner(self, "unitree_go2_flat")
