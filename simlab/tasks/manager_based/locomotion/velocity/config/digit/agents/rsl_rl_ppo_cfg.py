"""rsl_rl PPO for the Digit velocity tasks (Isaac Lab's published hyperparameters)."""

from simlab.utils import configclass

from ...common_ppo import VelocityRoughPPORunnerCfg, flat_runner


@configclass
class DigitRoughPPORunnerCfg(VelocityRoughPPORunnerCfg):
    max_iterations = 3000
    experiment_name = "digit_rough"


@configclass
class DigitFlatPPORunnerCfg(DigitRoughPPORunnerCfg):
    def __post_init__(self):
        flat_runner(self, "digit_flat", max_iterations=2000)
