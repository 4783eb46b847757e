"""Config classes for rsl_rl's student-teacher distillation (rsl-rl-lib 5.x), as in Isaac Lab's
``isaaclab_rl.rsl_rl.distillation_cfg``.

A teacher (a policy trained with PPO, often on privileged observations) is loaded from its checkpoint;
the student acts in the env and learns to output the teacher's actions on the states it visits
(rsl_rl's ``Distillation``: behaviour cloning on the student's own rollouts, DAgger-style).
``RslRlDistillationRunnerCfg.to_rsl_rl_dict()`` gives the dict ``rsl_rl.runners.DistillationRunner``
reads: ``obs_groups`` (the ``student`` and ``teacher`` observation sets), the two model dicts and the
``algorithm``. The teacher's model config must match the policy the teacher was trained as (its
``actor``, including the output distribution), or its checkpoint does not load.
"""

from __future__ import annotations

from dataclasses import MISSING
from typing import ClassVar, Literal

from simlab.utils import configclass

from .rl_cfg import RslRlBaseRunnerCfg, RslRlMLPModelCfg

__all__ = [
    "RslRlDistillationAlgorithmCfg",
    "RslRlDistillationRunnerCfg",
    "RslRlDistillationStudentTeacherCfg",
]


@configclass
class RslRlDistillationAlgorithmCfg:
    """The keyword arguments of ``rsl_rl.algorithms.Distillation``."""

    class_name: str = "Distillation"
    num_learning_epochs: int = MISSING
    """Passes over each rollout."""
    learning_rate: float = MISSING
    """The student's learning rate."""
    gradient_length: int = MISSING
    """Rollout steps whose losses are summed before each gradient step."""
    max_grad_norm: float | None = None
    """Clip the gradient's norm to this; None does not clip."""
    optimizer: Literal["adam", "adamw", "sgd", "rmsprop"] = "adam"
    loss_type: Literal["mse", "huber"] = "mse"
    """The behaviour loss between the student's and the teacher's actions."""


@configclass
class RslRlDistillationStudentTeacherCfg:
    """Deprecated (rsl-rl < 4) student-teacher config; converted to ``student`` / ``teacher`` MLPs."""

    class_name: str = "StudentTeacher"
    init_noise_std: float = MISSING
    noise_std_type: Literal["scalar", "log"] = "scalar"
    student_obs_normalization: bool = False
    teacher_obs_normalization: bool = False
    student_hidden_dims: list[int] = MISSING
    teacher_hidden_dims: list[int] = MISSING
    activation: str = MISSING


@configclass
class RslRlDistillationRunnerCfg(RslRlBaseRunnerCfg):
    """The distillation runner (rsl_rl ``DistillationRunner``): the runner settings, student and teacher
    models, and algorithm."""

    class_name: str = "DistillationRunner"
    """The rsl_rl runner this config is for (simlab train picks the runner by it, as Isaac Lab's train.py does)."""
    student: RslRlMLPModelCfg = MISSING
    """The student model (an MLP, or :class:`~simlab.rl.rsl_rl.RslRlCNNModelCfg` for image groups); its
    distribution's ``init_std`` is the exploration noise of its rollouts (the loss never changes it)."""
    teacher: RslRlMLPModelCfg = MISSING
    """The teacher model: the architecture of the policy in the teacher's checkpoint."""
    algorithm: RslRlDistillationAlgorithmCfg = MISSING
    policy: RslRlDistillationStudentTeacherCfg | None = None
    """Deprecated: set ``student`` and ``teacher`` instead."""

    _not_for_rsl_rl: ClassVar[tuple[str, ...]] = ("policy", "class_name")

    def _without_deprecated(self) -> RslRlDistillationRunnerCfg:
        return _convert_deprecated(self)

    def _fill_obs_groups(self, obs_groups: dict[str, list[str]], env_groups: list[str]) -> dict[str, list[str]]:
        """A set left out reads the env group of its name ("student" falls back to "policy"); simlab
        refuses a teacher that would silently read the student's observations because the env has no
        "teacher" group."""
        obs_groups.setdefault("student", ["student"] if "student" in env_groups else ["policy"])
        obs_groups.setdefault("teacher", ["teacher"])  # never the student's own groups by default
        return obs_groups


def _convert_deprecated(cfg: RslRlDistillationRunnerCfg) -> RslRlDistillationRunnerCfg:
    """Turn the deprecated ``policy`` field into ``student`` and ``teacher`` MLPs (the teacher with
    the Gaussian output a PPO actor has, so that its checkpoint loads; its noise is never used)."""
    cfg = cfg.copy()
    p = cfg.policy
    if p is None or p is MISSING:
        return cfg
    if cfg.student is not MISSING or cfg.teacher is not MISSING:
        raise ValueError("Set either 'policy' (deprecated) or 'student' and 'teacher', not both.")
    if p.class_name != "StudentTeacher":
        raise ValueError(
            f"policy.class_name '{p.class_name}' has no rsl-rl 5 equivalent here; only 'StudentTeacher' is converted."
            " Use student/teacher = RslRlMLPModelCfg(...)."
        )

    def mlp(hidden: list[int], normalize: bool, std: float) -> RslRlMLPModelCfg:
        return RslRlMLPModelCfg(
            hidden_dims=list(hidden),
            activation=p.activation,
            obs_normalization=normalize,
            distribution_cfg=RslRlMLPModelCfg.GaussianDistributionCfg(init_std=std, std_type=p.noise_std_type),
        )

    cfg.student = mlp(p.student_hidden_dims, p.student_obs_normalization, p.init_noise_std)
    cfg.teacher = mlp(p.teacher_hidden_dims, p.teacher_obs_normalization, 0.0)
    cfg.policy = None
    return cfg
