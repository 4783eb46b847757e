"""Configs of the demonstration recorder terms and of the manager that records all of them."""

from simlab.managers.manager_term_cfg import RecorderTermCfg
from simlab.managers.recorder_manager import RecorderManagerBaseCfg
from simlab.utils import configclass

from . import recorders


@configclass
class InitialStateRecorderCfg(RecorderTermCfg):
    class_type: type = recorders.InitialStateRecorder


@configclass
class PostStepStatesRecorderCfg(RecorderTermCfg):
    class_type: type = recorders.PostStepStatesRecorder


@configclass
class PreStepActionsRecorderCfg(RecorderTermCfg):
    class_type: type = recorders.PreStepActionsRecorder


@configclass
class PreStepFlatPolicyObservationsRecorderCfg(RecorderTermCfg):
    class_type: type = recorders.PreStepFlatPolicyObservationsRecorder


@configclass
class PreStepSubtaskTermsObservationsRecorderCfg(RecorderTermCfg):
    class_type: type = recorders.PreStepSubtaskTermsObservationsRecorder


@configclass
class PostStepProcessedActionsRecorderCfg(RecorderTermCfg):
    class_type: type = recorders.PostStepProcessedActionsRecorder


@configclass
class ActionStateRecorderManagerCfg(RecorderManagerBaseCfg):
    """Records what replaying a demonstration needs (initial state, actions) and what checks it (states)."""

    record_initial_state = InitialStateRecorderCfg()
    record_post_step_states = PostStepStatesRecorderCfg()
    record_pre_step_actions = PreStepActionsRecorderCfg()
    record_pre_step_flat_policy_observations = PreStepFlatPolicyObservationsRecorderCfg()
    record_post_step_processed_actions = PostStepProcessedActionsRecorderCfg()
