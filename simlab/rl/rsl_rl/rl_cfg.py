"""Config classes for rsl_rl's on-policy runner (rsl-rl-lib 5.x), as in Isaac Lab's ``isaaclab_rl.rsl_rl``.

``RslRlOnPolicyRunnerCfg.to_rsl_rl_dict()`` gives the dict that ``rsl_rl.runners.OnPolicyRunner``
reads: ``obs_groups``, the ``actor`` / ``critic`` model dicts (``class_name`` + ``MLPModel`` kwargs,
``distribution_cfg`` for a stochastic actor), and ``algorithm`` (``class_name`` + ``PPO`` kwargs).
The pre-4.0 ``policy = RslRlPpoActorCriticCfg(...)`` form is still accepted and converted.
``RslRlBaseRunnerCfg`` holds the settings every runner config shares (the distillation one derives from it too).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from dataclasses import MISSING, field
from typing import Any, ClassVar, Literal

from simlab.utils import configclass

__all__ = [
    "RslRlBaseRunnerCfg",
    "RslRlCNNModelCfg",
    "RslRlMLPModelCfg",
    "RslRlOnPolicyRunnerCfg",
    "RslRlPpoActorCriticCfg",
    "RslRlPpoAlgorithmCfg",
    "RslRlSymmetryCfg",
]


def _default_device() -> str:
    from simlab.utils.device import resolve_device

    return resolve_device(None)


@configclass
class RslRlMLPModelCfg:
    """An MLP model (rsl_rl ``MLPModel``): the actor (with an output distribution) or the critic."""

    @configclass
    class GaussianDistributionCfg:
        """Gaussian output with a state-independent, learned standard deviation."""

        class_name: str = "GaussianDistribution"
        init_std: float = 1.0
        """Initial standard deviation of the actions."""
        std_type: Literal["scalar", "log"] = "scalar"
        """Parameterization of the standard deviation."""

    class_name: str = "MLPModel"
    hidden_dims: list[int] = MISSING
    """Hidden layer sizes."""
    activation: str = "elu"
    """Activation function name ('elu', 'relu', 'tanh', ...)."""
    obs_normalization: bool = False
    """Normalize the model's input with running mean and variance."""
    distribution_cfg: GaussianDistributionCfg | None = None
    """Output distribution (the actor's); None gives a deterministic output (the critic)."""


@configclass
class RslRlCNNModelCfg(RslRlMLPModelCfg):
    """A CNN model (rsl_rl ``CNNModel``): convolutions over each image observation group, then the MLP.

    simlab's rsl_rl wrapper hands image groups to rsl_rl channels first, (N, C, H, W), as its CNNs take them.
    """

    @configclass
    class CNNCfg:
        """Keyword arguments of ``rsl_rl.modules.CNN`` (one value, or one per layer)."""

        output_channels: list[int] = MISSING
        kernel_size: int | list[int] = MISSING
        stride: int | list[int] = 1
        dilation: int | list[int] = 1
        padding: Literal["none", "zeros", "reflect", "replicate", "circular"] = "none"
        norm: str | list[str] = "none"
        activation: str = "elu"
        max_pool: bool | list[bool] = False
        global_pool: Literal["none", "max", "avg"] = "none"
        flatten: bool = True

    class_name: str = "CNNModel"
    cnn_cfg: CNNCfg = MISSING


@configclass
class RslRlPpoActorCriticCfg:
    """Deprecated (rsl-rl < 4) actor-critic config; converted to ``actor`` / ``critic`` models."""

    class_name: str = "ActorCritic"
    init_noise_std: float = MISSING
    noise_std_type: Literal["scalar", "log"] = "scalar"
    actor_obs_normalization: bool = False
    critic_obs_normalization: bool = False
    actor_hidden_dims: list[int] = MISSING
    critic_hidden_dims: list[int] = MISSING
    activation: str = MISSING


@configclass
class RslRlSymmetryCfg:
    """Symmetry in training (rsl_rl's ``Symmetry`` extension, Mittal et al. 2024): mirrored copies of the
    samples in every mini-batch (``use_data_augmentation``) and/or a loss on the policy's disagreement with
    its mirror image (``use_mirror_loss``); with both off the symmetry loss is only logged."""

    use_data_augmentation: bool = False
    use_mirror_loss: bool = False
    data_augmentation_func: Callable = MISSING
    """``f(env, obs, actions) -> (obs, actions)``: the batch followed by its mirrored copies (either may
    be None); e.g. ``simlab.tasks.manager_based.classic.cartpole.mdp.symmetry.compute_symmetric_states``."""
    mirror_loss_coeff: float = 0.0


@configclass
class RslRlPpoAlgorithmCfg:
    """PPO hyperparameters (the keyword arguments of ``rsl_rl.algorithms.PPO``)."""

    class_name: str = "PPO"
    num_learning_epochs: int = MISSING
    num_mini_batches: int = MISSING
    learning_rate: float = MISSING
    schedule: str = "adaptive"
    """'adaptive' (learning rate follows desired_kl) or 'fixed'."""
    gamma: float = MISSING
    lam: float = MISSING
    entropy_coef: float = MISSING
    desired_kl: float = MISSING
    max_grad_norm: float = MISSING
    value_loss_coef: float = MISSING
    use_clipped_value_loss: bool = True
    clip_param: float = MISSING
    optimizer: Literal["adam", "adamw", "sgd", "rmsprop"] = "adam"
    normalize_advantage_per_mini_batch: bool = False
    rnd_cfg: dict | None = None
    """Random network distillation settings (rsl_rl's dict form), or None."""
    symmetry_cfg: RslRlSymmetryCfg | dict | None = None
    """Symmetry augmentation (:class:`RslRlSymmetryCfg`, or rsl_rl's dict form), or None."""


@configclass
class RslRlBaseRunnerCfg:
    """What every rsl_rl runner config has: seed, device, rollout length, iterations, observation sets,
    action clipping, logging and checkpoints. Each runner config adds its models and ``algorithm``."""

    seed: int = 42
    device: str = field(default_factory=_default_device)
    """Device of the learner (the CLI sets it to the simulation device)."""
    num_steps_per_env: int = MISSING
    """Environment steps per env collected in each iteration."""
    max_iterations: int = MISSING
    obs_groups: dict[str, list[str]] = {}
    """Observation sets -> env observation groups: ``{"actor": [...], "critic": [...]}`` for PPO,
    ``{"student": [...], "teacher": [...]}`` for distillation. ``to_rsl_rl_dict`` fills the sets left
    out from the env's groups, as each runner config's ``_fill_obs_groups`` says."""
    clip_actions: float | None = None
    """Clip actions (a distillation's: the student's) to [-clip_actions, clip_actions] in the wrapper;
    None does not clip."""
    check_for_nan: bool = True
    save_interval: int = MISSING
    """Iterations between checkpoints."""
    experiment_name: str = MISSING
    """Folder under ``logs/rsl_rl/``."""
    run_name: str = ""
    """Appended to the run folder's time stamp: ``<timestamp>_<run_name>``."""
    logger: Literal["tensorboard", "wandb", "neptune"] = "tensorboard"
    wandb_project: str = "simlab"
    neptune_project: str = "simlab"
    resume: bool = False
    load_run: str = ".*"
    """Run folder to resume from (regex; the latest match)."""
    load_checkpoint: str = "model_.*.pt"
    """Checkpoint file to resume from (regex; the latest match)."""

    _not_for_rsl_rl: ClassVar[tuple[str, ...]] = ()
    """Fields the rsl_rl runner does not take (simlab's own, deprecated ones), left out of its dict."""

    def to_rsl_rl_dict(self, obs_group_names: list[str] | None = None) -> dict[str, Any]:
        """The dict the rsl_rl runner takes; ``obs_group_names`` (the env's groups) fills ``obs_groups``."""
        cfg = self._without_deprecated()
        cfg.validate()
        d = cfg.to_dict()
        for key in self._not_for_rsl_rl:
            d.pop(key, None)
        d["obs_groups"] = self._fill_obs_groups(dict(d["obs_groups"]), list(obs_group_names or ["policy"]))
        return d

    def _without_deprecated(self) -> RslRlBaseRunnerCfg:
        """A copy with the deprecated fields turned into their replacements."""
        return self.copy()

    def _fill_obs_groups(self, obs_groups: dict[str, list[str]], env_groups: list[str]) -> dict[str, list[str]]:
        """``obs_groups`` with the sets it leaves out read from ``env_groups``."""
        return obs_groups


@configclass
class RslRlOnPolicyRunnerCfg(RslRlBaseRunnerCfg):
    """The PPO runner (rsl_rl ``OnPolicyRunner``): the runner settings, actor, critic and algorithm."""

    fast_update: bool | None = None
    """simlab's PPO update (:mod:`simlab.rl.rsl_rl.fast_update`): rsl_rl's update math with no host
    read per mini-batch, replayed as one CUDA graph on the GPU. None: on CUDA wherever it covers
    the config (feed-forward models, Adam/AdamW, no RND/symmetry/multi-GPU), else rsl_rl's own
    update (on the CPU it gains nothing); True: used, also on the CPU (an error says what it does not
    cover); False: rsl_rl's own ``PPO.update``."""
    graph_act: bool | None = None
    """rsl_rl's ``alg.act`` (the policy's sample, value and log-probability each rollout step)
    replayed as one CUDA graph (:mod:`simlab.rl.rsl_rl.graphed_act`). None: on CUDA for feed-forward
    models; True: required (an error says why not); False: eager."""
    actor: RslRlMLPModelCfg = MISSING
    critic: RslRlMLPModelCfg = MISSING
    algorithm: RslRlPpoAlgorithmCfg = MISSING
    policy: RslRlPpoActorCriticCfg | None = None
    """Deprecated: set ``actor`` and ``critic`` instead."""
    empirical_normalization: bool | None = None
    """Deprecated: set ``obs_normalization`` of the models instead."""

    _not_for_rsl_rl: ClassVar[tuple[str, ...]] = ("policy", "empirical_normalization", "fast_update", "graph_act")

    def _without_deprecated(self) -> RslRlOnPolicyRunnerCfg:
        return _convert_deprecated(self)

    def _fill_obs_groups(self, obs_groups: dict[str, list[str]], env_groups: list[str]) -> dict[str, list[str]]:
        """Empty: the actor reads "policy", the critic "critic" if the env has that group, else "policy"."""
        if obs_groups:
            return obs_groups
        return {"actor": ["policy"], "critic": ["critic"] if "critic" in env_groups else ["policy"]}


def _convert_deprecated(cfg: RslRlOnPolicyRunnerCfg) -> RslRlOnPolicyRunnerCfg:
    """Turn the deprecated ``policy`` / ``empirical_normalization`` fields into ``actor`` / ``critic``."""
    cfg = cfg.copy()
    p = cfg.policy
    if p is not None and p is not MISSING:
        if cfg.actor is not MISSING or cfg.critic is not MISSING:
            raise ValueError("Set either 'policy' (deprecated) or 'actor' and 'critic', not both.")
        if p.class_name != "ActorCritic":
            raise ValueError(
                f"policy.class_name '{p.class_name}' has no rsl-rl 5 equivalent here; only 'ActorCritic' is converted."
                " Use actor/critic = RslRlMLPModelCfg(...)."
            )
        cfg.actor = RslRlMLPModelCfg(
            hidden_dims=list(p.actor_hidden_dims),
            activation=p.activation,
            obs_normalization=p.actor_obs_normalization,
            distribution_cfg=RslRlMLPModelCfg.GaussianDistributionCfg(
                init_std=p.init_noise_std, std_type=p.noise_std_type
            ),
        )
        cfg.critic = RslRlMLPModelCfg(
            hidden_dims=list(p.critic_hidden_dims),
            activation=p.activation,
            obs_normalization=p.critic_obs_normalization,
        )
        cfg.policy = None
    if cfg.empirical_normalization is not None:
        for model in (cfg.actor, cfg.critic):
            if dataclasses.is_dataclass(model):
                model.obs_normalization = bool(cfg.empirical_normalization)
        cfg.empirical_normalization = None
    return cfg
