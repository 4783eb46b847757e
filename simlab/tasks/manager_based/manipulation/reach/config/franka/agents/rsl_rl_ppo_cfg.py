"""rsl_rl PPO for the Franka reach task (Isaac Lab's published hyperparameters)."""

from simlab.rl.rsl_rl import RslRlMLPModelCfg, RslRlOnPolicyRunnerCfg, RslRlPpoAlgorithmCfg
from simlab.utils import configclass


@configclass
class FrankaReachPPORunnerCfg(RslRlOnPolicyRunnerCfg):
    num_steps_per_env = 24
    max_iterations = 1000
    save_interval = 50
    experiment_name = "franka_reach"
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
        entropy_coef=0.001,
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
class FrankaReachNormalizedPPORunnerCfg(FrankaReachPPORunnerCfg):
    """Isaac Lab's reach agent with normalized observations and the lift agent's larger networks; the
    agent of every Franka reach task (joint-position, IK and OSC actions).

    The policy must turn the commanded position into actions, and that part of its input spans a few
    tenths of a metre (x 0.35-0.65 m, std 0.09 m) beside quaternions, joint angles and last actions
    of order 1: unnormalized, the policy followed the commanded orientation and barely the position,
    and more training made the position worse. The commanded yaw needs joint 7 near or past its
    limits for a quarter of the commands, a mapping [64, 64] networks learned slowly.
    CPU, 512 envs, mean errors over 192 held-out windows (docs/manipulation.md, "Why the position
    error grew"): joint-position actions, Isaac Lab's agent 8.05 cm / 0.200 rad at iteration 200 and
    7.85 cm / 0.114 rad at 399; normalized, at iteration 250: 2.04 cm / 0.240 rad with [64, 64],
    1.19 cm / 0.104 rad with [256, 128, 64]. IK-Abs actions (384 windows): Isaac Lab's agent 5.46 cm
    after 1,336 iterations, this one 1.82 cm / 0.111 rad after 400 (docs/manipulation.md).
    """

    def __post_init__(self):
        for model in (self.actor, self.critic):
            model.obs_normalization = True
            model.hidden_dims = [256, 128, 64]
