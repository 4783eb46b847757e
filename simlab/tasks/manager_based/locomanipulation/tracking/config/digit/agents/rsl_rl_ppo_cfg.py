"""rsl_rl PPO for the Digit loco-manipulation task: Isaac Lab's published hyperparameters but the initial
action noise, 0.5 instead of 1.0. A fall costs the termination penalty once, a second alive what the terms
sum to; below -100 x (1 - gamma) = -1 per second, ending the episode pays more than balancing. Under
noise 1.0 a robot alive in this task earns -1.6 per second (its hands still 0.2 m from their targets, the
noise charged by action_rate_l2), under 0.5 -0.8 (tests/test_digit_locomanip.py)."""

from simlab.rl.rsl_rl import RslRlMLPModelCfg, RslRlOnPolicyRunnerCfg, RslRlPpoAlgorithmCfg
from simlab.utils import configclass


@configclass
class DigitLocoManipPPORunnerCfg(RslRlOnPolicyRunnerCfg):
    num_steps_per_env = 24
    max_iterations = 2000
    save_interval = 50
    experiment_name = "digit_loco_manip"
    actor = RslRlMLPModelCfg(
        hidden_dims=[256, 128, 128],
        activation="elu",
        obs_normalization=False,
        distribution_cfg=RslRlMLPModelCfg.GaussianDistributionCfg(init_std=0.5),
    )
    critic = RslRlMLPModelCfg(hidden_dims=[256, 128, 128], activation="elu", obs_normalization=False)
    algorithm = RslRlPpoAlgorithmCfg(
        value_loss_coef=1.0,
        use_clipped_value_loss=True,
        clip_param=0.2,
        entropy_coef=0.01,
        num_learning_epochs=5,
        num_mini_batches=4,
        learning_rate=1.0e-3,
        schedule="adaptive",
        gamma=0.99,
        lam=0.95,
        desired_kl=0.01,
        max_grad_norm=1.0,
    )
