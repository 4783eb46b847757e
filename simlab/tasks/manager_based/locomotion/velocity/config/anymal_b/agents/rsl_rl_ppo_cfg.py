"""rsl_rl PPO for the ANYmal-B velocity tasks (Isaac Lab's published hyperparameters)."""

from simlab.rl.rsl_rl import RslRlOnPolicyRunnerCfg, RslRlSymmetryCfg
from simlab.tasks.manager_based.locomotion.velocity.mdp.symmetry import anymal
from simlab.utils import configclass

from ...common_ppo import VelocityRoughPPORunnerCfg, flat_runner, ppo


@configclass
class AnymalBRoughPPORunnerCfg(VelocityRoughPPORunnerCfg):
    experiment_name = "anymal_b_rough"
    algorithm = ppo(entropy_coef=0.005)


@configclass
class AnymalBFlatPPORunnerCfg(AnymalBRoughPPORunnerCfg):
    def __post_init__(self):
        flat_runner(self, "anymal_b_flat", init_std=0.5)


def _with_symmetry(runner: RslRlOnPolicyRunnerCfg) -> None:
    runner.algorithm.symmetry_cfg = RslRlSymmetryCfg(
        use_data_augmentation=True, data_augmentation_func=anymal.compute_symmetric_states
    )


@configclass
class AnymalBFlatPPORunnerWithSymmetryCfg(AnymalBFlatPPORunnerCfg):
    """The same PPO, every mini-batch augmented by its three mirror images (``--agent
    rsl_rl_with_symmetry_cfg_entry_point``)."""

    def __post_init__(self):
        super().__post_init__()
        _with_symmetry(self)


@configclass
class AnymalBRoughPPORunnerWithSymmetryCfg(AnymalBRoughPPORunnerCfg):
    """The same PPO, every mini-batch augmented by its three mirror images (``--agent
    rsl_rl_with_symmetry_cfg_entry_point``)."""

    def __post_init__(self):
        _with_symmetry(self)
