"""rsl_rl PPO for the Cassie velocity tasks (Isaac Lab's published hyperparameters)."""

from simlab.utils import configclass

from ...common_ppo import VelocityRoughPPORunnerCfg, flat_runner


@configclass
class CassieRoughPPORunnerCfg(VelocityRoughPPORunnerCfg):
    experiment_name = "cassie_rough"


@configclass
class CassieFlatPPORunnerCfg(CassieRoughPPORunnerCfg):
    def __post_init__(self):
        flat_runner(self, "cassie_flat", max_iterations=1000)
