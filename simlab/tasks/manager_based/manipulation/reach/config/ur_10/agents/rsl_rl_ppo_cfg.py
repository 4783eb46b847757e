"""rsl_rl PPO for the UR10 reach task: Isaac Lab's published hyperparameters, and the registered variant."""

from simlab.rl.rsl_rl import RslRlMLPModelCfg, RslRlOnPolicyRunnerCfg, RslRlPpoAlgorithmCfg
from simlab.utils import configclass


@configclass
class UR10ReachPPORunnerCfg(RslRlOnPolicyRunnerCfg):
    num_steps_per_env = 24
    max_iterations = 1000
    save_interval = 50
    experiment_name = "reach_ur10"
    actor = RslRlMLPModelCfg(
        hidden_dims=[64, 64],
        activation="elu",
        obs_normalization=False,
        distribution_cfg=RslRlMLPModelCfg.GaussianDistributionCfg(init_std=1.0),
    )
    critic = RslRlMLPModelCfg(hidden_dims=[64, 64], activation="elu", obs_normalization=False)
    algorithm = RslRlPpoAlgorithmCfg(
        value_loss_coef=1.0,
        use_clipped_value_loss=True,
        clip_param=0.2,
        entropy_coef=0.01,
        num_learning_epochs=8,
        num_mini_batches=4,
        learning_rate=1.0e-3,
        schedule="adaptive",
        gamma=0.99,
        lam=0.95,
        desired_kl=0.01,
        max_grad_norm=1.0,
    )


@configclass
class UR10ReachNormalizedPPORunnerCfg(UR10ReachPPORunnerCfg):
    """Isaac Lab's UR10 reach agent with normalized observations and [256, 128, 64] networks, the
    registered agent of ``simlab/Reach-UR10-v0``: the change that made the Franka reach tasks meet the
    reach criterion (see ``FrankaReachNormalizedPPORunnerCfg``). The observations are the same (joint
    states, the commanded pose in the root frame, last actions), and the commanded position, a few
    tenths of a metre wide, is what an unnormalized policy barely followed there."""

    def __post_init__(self):
        for model in (self.actor, self.critic):
            model.obs_normalization = True
            model.hidden_dims = [256, 128, 64]
