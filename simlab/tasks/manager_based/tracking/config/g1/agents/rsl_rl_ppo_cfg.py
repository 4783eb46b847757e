"""rsl_rl PPO for G1 motion tracking: mjlab's hyperparameters (512-256-128 ELU, empirical observation
normalization, 30 000 iterations of 24 steps) but for the initial action noise, 0.5 instead of 1.0.

At 1.0 the first actions' changes cost more than tracking pays (action_rate_l2: 0.1 x 2 x 29 x 1.0^2 =
5.8 per second against at most 5 for perfect tracking), so every step alive loses reward and PPO learns
to end its episodes: on the CPU (256 envs, g1_walk, seed 1) the episodes shrank from 34 to 13 steps in
30 iterations and to 5 in 60 (the noise still 0.94), the policy swinging a wrist out of its 0.25 m band.
At 0.5 (1.45 per second) the same run kept positive rewards and its episodes grew from 37 to 43-47 steps
in 60 iterations (tests/test_humanoid_tracking.py::test_staying_alive_pays_at_the_agents_initial_action_noise).
"""

from simlab.rl.rsl_rl import RslRlMLPModelCfg, RslRlOnPolicyRunnerCfg, RslRlPpoAlgorithmCfg
from simlab.utils import configclass


@configclass
class G1FlatTrackingPPORunnerCfg(RslRlOnPolicyRunnerCfg):
    num_steps_per_env = 24
    max_iterations = 30000
    save_interval = 500
    experiment_name = "g1_tracking"
    obs_groups = {"actor": ["policy"], "critic": ["critic"]}
    actor = RslRlMLPModelCfg(
        hidden_dims=[512, 256, 128],
        activation="elu",
        obs_normalization=True,
        distribution_cfg=RslRlMLPModelCfg.GaussianDistributionCfg(init_std=0.5),  # mjlab: 1.0 (see above)
    )
    critic = RslRlMLPModelCfg(hidden_dims=[512, 256, 128], activation="elu", obs_normalization=True)
    algorithm = RslRlPpoAlgorithmCfg(
        value_loss_coef=1.0,
        use_clipped_value_loss=True,
        clip_param=0.2,
        entropy_coef=0.005,
        num_learning_epochs=5,
        num_mini_batches=4,
        learning_rate=1.0e-3,
        schedule="adaptive",
        gamma=0.99,
        lam=0.95,
        desired_kl=0.01,
        max_grad_norm=1.0,
    )
