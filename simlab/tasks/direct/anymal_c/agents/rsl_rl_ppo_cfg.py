"""rsl_rl PPO for the direct ANYmal-C velocity tasks (Isaac Lab's published hyperparameters)."""

from simlab.rl.rsl_rl import RslRlMLPModelCfg, RslRlOnPolicyRunnerCfg, RslRlPpoAlgorithmCfg
from simlab.utils import configclass


def _ppo() -> RslRlPpoAlgorithmCfg:
    return RslRlPpoAlgorithmCfg(
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


def _mlp(hidden_dims: list[int], actor: bool) -> RslRlMLPModelCfg:
    distribution = RslRlMLPModelCfg.GaussianDistributionCfg(init_std=1.0) if actor else None
    return RslRlMLPModelCfg(
        hidden_dims=hidden_dims, activation="elu", obs_normalization=False, distribution_cfg=distribution
    )


@configclass
class AnymalCFlatPPORunnerCfg(RslRlOnPolicyRunnerCfg):
    num_steps_per_env = 24
    max_iterations = 500
    save_interval = 50
    experiment_name = "anymal_c_flat_direct"
    actor = _mlp([128, 128, 128], actor=True)
    critic = _mlp([128, 128, 128], actor=False)
    algorithm = _ppo()


@configclass
class AnymalCRoughPPORunnerCfg(RslRlOnPolicyRunnerCfg):
    num_steps_per_env = 24
    max_iterations = 1500
    save_interval = 50
    experiment_name = "anymal_c_rough_direct"
    actor = _mlp([512, 256, 128], actor=True)
    critic = _mlp([512, 256, 128], actor=False)
    algorithm = _ppo()
