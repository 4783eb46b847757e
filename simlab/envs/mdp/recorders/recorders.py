"""What a demonstration holds: the state an episode starts from, the actions, the states after each
step and the policy observations (and a task's subtask signals); ``env.reset_to(initial_state)`` plus
the actions replays it."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import torch

from simlab.managers.recorder_manager import RecorderTerm


def _rows(value: Any, env_ids: Sequence[int]) -> Any:
    if isinstance(value, dict):
        return {key: _rows(sub, env_ids) for key, sub in value.items()}
    return value[list(env_ids)]


class InitialStateRecorder(RecorderTerm):
    """``initial_state``: the scene state (env-relative) of the envs that just reset."""

    def record_post_reset(self, env_ids: Sequence[int] | None):
        state = self._env.scene.get_state(is_relative=True)
        return "initial_state", state if env_ids is None else _rows(state, env_ids)


class PostStepStatesRecorder(RecorderTerm):
    """``states``: the scene state (env-relative) at the end of each step."""

    def record_post_step(self):
        return "states", self._env.scene.get_state(is_relative=True)


class PreStepActionsRecorder(RecorderTerm):
    """``actions``: the action given to each step."""

    def record_pre_step(self):
        return "actions", self._env.action_manager.action


class PreStepFlatPolicyObservationsRecorder(RecorderTerm):
    """``obs``: the ``policy`` observation group the action was chosen from."""

    def record_pre_step(self):
        return "obs", self._env.obs_buf["policy"]


class PreStepSubtaskTermsObservationsRecorder(RecorderTerm):
    """``obs/subtask_term_signals``: the ``subtask_terms`` observation group (a task's subtask signals,
    e.g. the stack task's grasp_1, stack_1, grasp_2) the action was chosen from."""

    def record_pre_step(self):
        return "obs/subtask_term_signals", self._env.obs_buf["subtask_terms"]


class PostStepProcessedActionsRecorder(RecorderTerm):
    """``processed_actions``: every action term's processed action, concatenated."""

    def record_post_step(self):
        manager = self._env.action_manager
        parts = [manager.get_term(name).processed_actions.clone() for name in manager.active_terms]
        return "processed_actions", torch.cat(parts, dim=-1) if parts else None
