"""rsl_rl PPO for the G1 velocity tasks (Isaac Lab's published hyperparameters)."""

from simlab.utils import configclass

from ...common_ppo import VelocityRoughPPORunnerCfg, flat_runner, ppo


@configclass
class G1RoughPPORunnerCfg(VelocityRoughPPORunnerCfg):
    max_iterations = 3000
    experiment_name = "g1_rough"
    algorithm = ppo(entropy_coef=0.008)


@configclass
class G1FlatPPORunnerCfg(G1RoughPPORunnerCfg):
    def __post_init__(self):
        flat_runner(self, "g1_flat", max_iterations=1500, hidden_dims=(256, 128, 128))
