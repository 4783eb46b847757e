"""Recorder terms for demonstrations: initial state, per-step states, actions, observations and subtask
signals."""

from .recorders import (
    InitialStateRecorder,
    PostStepProcessedActionsRecorder,
    PostStepStatesRecorder,
    PreStepActionsRecorder,
    PreStepFlatPolicyObservationsRecorder,
    PreStepSubtaskTermsObservationsRecorder,
)
from .recorders_cfg import (
    ActionStateRecorderManagerCfg,
    InitialStateRecorderCfg,
    PostStepProcessedActionsRecorderCfg,
    PostStepStatesRecorderCfg,
    PreStepActionsRecorderCfg,
    PreStepFlatPolicyObservationsRecorderCfg,
    PreStepSubtaskTermsObservationsRecorderCfg,
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
    "PreStepSubtaskTermsObservationsRecorder",
    "PreStepSubtaskTermsObservationsRecorderCfg",
]
