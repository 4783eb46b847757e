"""rsl_rl distillation for the cartpoles: a student learns the actions of the state cartpole's PPO policy
(``simlab/Cartpole-v0``'s, e.g. the shipped one) on the states it visits itself.

    simlab train --task simlab/Cartpole-v0 --agent rsl_rl_distillation_cfg_entry_point --checkpoint <teacher>
    simlab train --task simlab/Cartpole-Depth-v0 --agent rsl_rl_distillation_cfg_entry_point --checkpoint <teacher>

The teacher is the PPO actor of :class:`.rsl_rl_ppo_cfg.CartpolePPORunnerCfg` (32 x 32 ELU, a Gaussian
output whose noise the teacher never uses) reading the cart's and pole's joint positions and velocities:
the state cartpole's ``policy`` group, the camera cartpoles' ``teacher`` group. The camera student is a
small CNN on the depth image's last three frames.
"""

from simlab.rl.rsl_rl import (
    RslRlCNNModelCfg,
    RslRlDistillationAlgorithmCfg,
    RslRlDistillationRunnerCfg,
    RslRlMLPModelCfg,
)
from simlab.utils import configclass

_TEACHER = RslRlMLPModelCfg(
    hidden_dims=[32, 32],
    activation="elu",
    obs_normalization=False,
    distribution_cfg=RslRlMLPModelCfg.GaussianDistributionCfg(init_std=0.0),
)


@configclass
class CartpoleDistillationRunnerCfg(RslRlDistillationRunnerCfg):
    """The state cartpole's student: an MLP on the same state as the teacher (a check of the pipeline)."""

    num_steps_per_env = 16
    max_iterations = 60
    save_interval = 20
    experiment_name = "cartpole"  # the teacher's, as Isaac Lab does: --load_run <teacher run> finds it there
    obs_groups = {"student": ["policy"], "teacher": ["policy"]}
    student = RslRlMLPModelCfg(
        hidden_dims=[32, 32],
        activation="elu",
        obs_normalization=False,
        # the exploration noise of the student's rollouts (relative to the teacher's actions, about 1)
        distribution_cfg=RslRlMLPModelCfg.GaussianDistributionCfg(init_std=0.1),
    )
    teacher = _TEACHER
    algorithm = RslRlDistillationAlgorithmCfg(num_learning_epochs=2, learning_rate=1.0e-3, gradient_length=2)


@configclass
class CartpoleCameraDistillationRunnerCfg(RslRlDistillationRunnerCfg):
    """The camera cartpole's student: a small CNN on the image group's frames (their channels stacked)."""

    num_steps_per_env = 32
    max_iterations = 300
    save_interval = 10
    experiment_name = "cartpole_camera_distillation"
    obs_groups = {"student": ["policy"], "teacher": ["teacher"]}
    student = RslRlCNNModelCfg(
        hidden_dims=[64],
        activation="elu",
        obs_normalization=False,
        cnn_cfg=RslRlCNNModelCfg.CNNCfg(
            output_channels=[16, 32, 32], kernel_size=[8, 4, 3], stride=[4, 2, 2], activation="relu"
        ),
        distribution_cfg=RslRlCNNModelCfg.GaussianDistributionCfg(init_std=0.1),
    )
    teacher = _TEACHER
    # rendering is the cost of a sample here, the update of the small CNN a tenth of it: four passes, a
    # gradient step per rollout step; Huber's loss keeps the teacher's large actions in states it never
    # learned (a fallen pole) from drowning out the rest while the student still drops the pole
    algorithm = RslRlDistillationAlgorithmCfg(
        num_learning_epochs=4, learning_rate=1.0e-3, gradient_length=1, loss_type="huber"
    )
