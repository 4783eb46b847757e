"""Isaac Lab's rsl_rl PPO for the velocity tasks, written once: its Go1, A1, Go2, ANYmal-B/C/D, G1, H1,
Cassie and Digit runners are the same but for the experiment name, the entropy bonus (ANYmal's 0.005,
G1's 0.008), the bipeds' longer training and the flat networks' widths."""

from __future__ import annotations

from simlab.rl.rsl_rl import RslRlMLPModelCfg, RslRlOnPolicyRunnerCfg, RslRlPpoAlgorithmCfg
from simlab.utils import configclass


def ppo(entropy_coef: float) -> RslRlPpoAlgorithmCfg:
    """Isaac Lab's velocity-task PPO (adaptive learning rate around a KL of 0.01)."""
    return RslRlPpoAlgorithmCfg(
        value_loss_coef=1.0,
        use_clipped_value_loss=True,
        clip_param=0.2,
        entropy_coef=entropy_coef,
        num_learning_epochs=5,
        num_mini_batches=4,
        learning_rate=1.0e-3,
        schedule="adaptive",
        gamma=0.99,
        lam=0.95,
        desired_kl=0.01,
        max_grad_norm=1.0,
    )


@configclass
class VelocityRoughPPORunnerCfg(RslRlOnPolicyRunnerCfg):
    """The rough task's runner: 24 steps per env and iteration, 512-256-128 ELU actor and critic."""

    num_steps_per_env = 24
    max_iterations = 1500
    save_interval = 50
    actor = RslRlMLPModelCfg(
        hidden_dims=[512, 256, 128],
        activation="elu",
        obs_normalization=False,
        distribution_cfg=RslRlMLPModelCfg.GaussianDistributionCfg(init_std=1.0),
    )
    critic = RslRlMLPModelCfg(hidden_dims=[512, 256, 128], activation="elu", obs_normalization=False)
    algorithm = ppo(entropy_coef=0.01)


def flat_runner(
    cfg: RslRlOnPolicyRunnerCfg,
    experiment_name: str,
    max_iterations: int = 300,
    hidden_dims: tuple[int, ...] = (128, 128, 128),
    init_std: float | None = None,
) -> None:
    """The flat task's runner from the rough one: fewer iterations, smaller networks (the quadrupeds'
    300 iterations and 128-128-128 unless given).

    ``init_std`` replaces Isaac Lab's initial action noise of 1.0 where simlab measured that it keeps
    the robot from learning: ANYmal-B/D and Go1 on flat ground (one H100, 4096 envs, seed 42) learned
    to fall at 1.0 (ANYmal-D scored 0.74 m/s after 300 iterations, Go1 0.73; bar 0.25) and walked at
    0.5 (ANYmal-D 0.17 after 100, ANYmal-B 0.23 after 100, Go1 0.17 after 300): their stiff drives
    turn a unit of action noise into large torques (docs/locomotion.md)."""
    if init_std is not None:
        cfg.actor.distribution_cfg.init_std = init_std
    cfg.max_iterations = max_iterations
    cfg.experiment_name = experiment_name
    cfg.actor.hidden_dims = list(hidden_dims)
    cfg.critic.hidden_dims = list(hidden_dims)
