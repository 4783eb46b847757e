"""rsl_rl PPO for the ANYmal-D velocity tasks (Isaac Lab's published hyperparameters)."""

from simlab.utils import configclass

from ...common_ppo import VelocityRoughPPORunnerCfg, flat_runner, ppo


@configclass
class AnymalDRoughPPORunnerCfg(VelocityRoughPPORunnerCfg):
    experiment_name = "anymal_d_rough"
    algorithm = ppo(entropy_coef=0.005)


@configclass
class AnymalDFlatPPORunnerCfg(AnymalDRoughPPORunnerCfg):
    def __post_init__(self):
        flat_runner(self, "anymal_d_flat", init_std=0.5)
