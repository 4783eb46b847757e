"""rsl_rl PPO for the H1 velocity tasks (Isaac Lab's published hyperparameters)."""

from simlab.utils import configclass

from ...common_ppo import VelocityRoughPPORunnerCfg, flat_runner


@configclass
class H1RoughPPORunnerCfg(VelocityRoughPPORunnerCfg):
    max_iterations = 3000
    experiment_name = "h1_rough"


@configclass
class H1FlatPPORunnerCfg(H1RoughPPORunnerCfg):
    def __post_init__(self):
        flat_runner(self, "h1_flat", max_iterations=1000)
