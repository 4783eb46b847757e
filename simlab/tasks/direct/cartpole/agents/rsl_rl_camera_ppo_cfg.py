"""rsl_rl PPO with a CNN for the cartpole camera tasks: the network and PPO settings of Isaac Lab's
rl_games camera config (three convolutions, 512 ELU units; learning rate 1e-4, 64 steps per env),
except that the last convolution strides 2: its map is 5 x 5 rather than 9 x 9 for 100 x 100 images,
so the layer after it has a third of the weights (the policy file 3.3 MB rather than 10.7 MB)."""

from simlab.rl.rsl_rl import RslRlCNNModelCfg, RslRlOnPolicyRunnerCfg, RslRlPpoAlgorithmCfg
from simlab.utils import configclass

_CNN = RslRlCNNModelCfg.CNNCfg(output_channels=[32, 64, 64], kernel_size=[8, 4, 3], stride=[4, 2, 2], activation="relu")


@configclass
class CartpoleCameraPPORunnerCfg(RslRlOnPolicyRunnerCfg):
    num_steps_per_env = 64
    max_iterations = 500
    save_interval = 25
    experiment_name = "cartpole_camera_direct"
    clip_actions = 1.0
    actor = RslRlCNNModelCfg(
        hidden_dims=[512],
        activation="elu",
        cnn_cfg=_CNN,
        distribution_cfg=RslRlCNNModelCfg.GaussianDistributionCfg(init_std=1.0),
    )
    critic = RslRlCNNModelCfg(hidden_dims=[512], activation="elu", cnn_cfg=_CNN)
    algorithm = RslRlPpoAlgorithmCfg(
        value_loss_coef=2.0,
        use_clipped_value_loss=True,
        clip_param=0.2,
        entropy_coef=0.0,
        num_learning_epochs=4,
        num_mini_batches=16,
        learning_rate=1.0e-4,
        schedule="adaptive",
        gamma=0.99,
        lam=0.95,
        desired_kl=0.008,
        max_grad_norm=1.0,
    )
