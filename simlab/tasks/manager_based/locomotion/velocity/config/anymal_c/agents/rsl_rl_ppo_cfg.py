"""rsl_rl PPO for the ANYmal-C velocity tasks (Isaac Lab's published hyperparameters)."""

from simlab.utils import configclass

from ...common_ppo import VelocityRoughPPORunnerCfg, flat_runner, ppo


@configclass
class AnymalCRoughPPORunnerCfg(VelocityRoughPPORunnerCfg):
    experiment_name = "anymal_c_rough"
    algorithm = ppo(entropy_coef=0.005)


@configclass
class AnymalCFlatPPORunnerCfg(AnymalCRoughPPORunnerCfg):
    def __post_init__(self):
        flat_runner(self, "anymal_c_flat")
