"""rsl_rl (rsl-rl-lib 5.x) support: the env wrapper, runner config classes (PPO and distillation) and policy export.

The config classes import without rsl_rl installed (task configs use them); the wrapper needs
``pip install "simlab[rsl_rl]"``.
"""

from typing import Any

from .distillation_cfg import (
    RslRlDistillationAlgorithmCfg,
    RslRlDistillationRunnerCfg,
    RslRlDistillationStudentTeacherCfg,
)
from .exporter import export_policy_as_jit, export_policy_as_onnx
from .rl_cfg import (
    RslRlBaseRunnerCfg,
    RslRlCNNModelCfg,
    RslRlMLPModelCfg,
    RslRlOnPolicyRunnerCfg,
    RslRlPpoActorCriticCfg,
    RslRlPpoAlgorithmCfg,
    RslRlSymmetryCfg,
)

__all__ = [
    "RslRlBaseRunnerCfg",
    "RslRlCNNModelCfg",
    "RslRlDistillationAlgorithmCfg",
    "RslRlDistillationRunnerCfg",
    "RslRlDistillationStudentTeacherCfg",
    "RslRlMLPModelCfg",
    "RslRlOnPolicyRunnerCfg",
    "RslRlPpoActorCriticCfg",
    "RslRlPpoAlgorithmCfg",
    "RslRlSymmetryCfg",
    "RslRlVecEnvWrapper",
    "export_policy_as_jit",
    "export_policy_as_onnx",
]


def __getattr__(name: str) -> Any:
    if name == "RslRlVecEnvWrapper":
        from .vecenv_wrapper import RslRlVecEnvWrapper

        return RslRlVecEnvWrapper
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
