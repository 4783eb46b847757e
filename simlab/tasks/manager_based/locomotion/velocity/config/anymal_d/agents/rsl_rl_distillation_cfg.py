"""rsl_rl distillation for ANYmal-D on flat ground (Isaac Lab's published settings): a 128-128-128 student
learns the actions of the flat task's PPO policy (the teacher, of the same size) from the same ``policy``
observations.

    simlab train --task simlab/Velocity-Flat-Anymal-D-v0                      # the teacher
    simlab train --task simlab/Velocity-Flat-Anymal-D-v0 --agent rsl_rl_distillation_cfg_entry_point \\
        --checkpoint <the teacher's run folder>
    simlab play --task simlab/Velocity-Flat-Anymal-D-v0 --agent rsl_rl_distillation_cfg_entry_point \\
        --use_last_checkpoint
"""

from simlab.rl.rsl_rl import RslRlDistillationAlgorithmCfg, RslRlDistillationRunnerCfg, RslRlMLPModelCfg
from simlab.utils import configclass


def _mlp(init_std: float) -> RslRlMLPModelCfg:
    return RslRlMLPModelCfg(
        hidden_dims=[128, 128, 128],
        activation="elu",
        obs_normalization=False,
        distribution_cfg=RslRlMLPModelCfg.GaussianDistributionCfg(init_std=init_std),
    )


@configclass
class AnymalDFlatDistillationRunnerCfg(RslRlDistillationRunnerCfg):
    num_steps_per_env = 120
    max_iterations = 300
    save_interval = 50
    experiment_name = "anymal_d_flat"
    obs_groups = {"student": ["policy"], "teacher": ["policy"]}
    student = _mlp(init_std=0.1)
    teacher = _mlp(init_std=0.0)  # the PPO actor's output layer and noise parameter, so its checkpoint loads
    algorithm = RslRlDistillationAlgorithmCfg(num_learning_epochs=2, learning_rate=1.0e-3, gradient_length=15)
