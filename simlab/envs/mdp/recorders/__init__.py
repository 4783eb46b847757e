"""Recorder terms for demonstrations: initial state, per-step states, actions and observations."""

from .recorders import (
    InitialStateRecorder,
    PostStepProcessedActionsRecorder,
    PostStepStatesRecorder,
    PreStepActionsRecorder,
    PreStepFlatPolicyObservationsRecorder,
)
from .recorders_cfg import (
    ActionStateRecorderManagerCfg,
    InitialStateRecorderCfg,
    PostStepProcessedActionsRecorderCfg,
    PostStepStatesRecorderCfg,
    PreStepActionsRecorderCfg,
    PreStepFlatPolicyObservationsRecorderCfg,
)

__all__ = [
    "ActionStateRecorderManagerCfg",
    "InitialStateRecorder",
    "InitialStateRecorderCfg",
    "PostStepProcessedActionsRecorder",
    "PostStepProcessedActionsRecorderCfg",
    "PostStepStatesRecorder",
    "PostStepStatesRecorderCfg",
    "PreStepActionsRecorder",
    "PreStepActionsRecorderCfg",
    "PreStepFlatPolicyObservationsRecorder",
    "PreStepFlatPolicyObservationsRecorderCfg",
]
