"""rsl_rl PPO for the Spot velocity task: Isaac Lab's published hyperparameters but for the initial
action noise, 0.5 where Isaac Lab has 1.0 (as simlab's Go1 and ANYmal-B/D flat runners): under noise
1.0 this model's robots fell every 3.3 s and their action-smoothness penalty alone cost 4.8 per second;
under 0.5 every 4.7 s (zero actions: 5.0 s, the task's resets throw them) and 2.4 per second (64 envs,
3 seeds, 6 s each, CPU; docs/locomotion.md)."""

from simlab.rl.rsl_rl import RslRlMLPModelCfg, RslRlOnPolicyRunnerCfg, RslRlPpoAlgorithmCfg
from simlab.utils import configclass


@configclass
class SpotFlatPPORunnerCfg(RslRlOnPolicyRunnerCfg):
    num_steps_per_env = 24
    max_iterations = 20000
    save_interval = 50
    experiment_name = "spot_flat"
    actor = RslRlMLPModelCfg(
        hidden_dims=[512, 256, 128],
        activation="elu",
        obs_normalization=False,
        distribution_cfg=RslRlMLPModelCfg.GaussianDistributionCfg(init_std=0.5),
    )
    critic = RslRlMLPModelCfg(hidden_dims=[512, 256, 128], activation="elu", obs_normalization=False)
    algorithm = RslRlPpoAlgorithmCfg(
        value_loss_coef=0.5,
        use_clipped_value_loss=True,
        clip_param=0.2,
        entropy_coef=0.0025,
        num_learning_epochs=5,
        num_mini_batches=4,
        learning_rate=1.0e-3,
        schedule="adaptive",
        gamma=0.99,
        lam=0.95,
        desired_kl=0.01,
        max_grad_norm=1.0,
    )
