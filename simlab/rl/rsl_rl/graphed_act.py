"""rsl_rl's ``alg.act`` (the policy's forward in the rollout) replayed as one CUDA graph.

Each rollout step rsl_rl's ``PPO.act`` runs the actor, samples an action, runs the critic and
takes the action's log-probability: some forty small kernels, each launched from Python. At a
few thousand envs their launches, not the GPU, set the step's time. :class:`GraphedAct` captures
rsl_rl's own ``act`` once (after a warm-up whose random draws are undone) and replays it each
step; the step's observations are copied into the graph's input first. The transition it fills
is rsl_rl's, with the graph's outputs in it (rsl_rl's storage copies them before the next step).

The graph reads the models' parameters and buffers by address; if one is replaced (rsl_rl's
observation normalizer assigns a new ``_std`` when simlab's fast update is off), it recaptures.
"""

from __future__ import annotations

from typing import Any

import torch

from simlab.rl.utils import require

from .capturable import capturable_distributions, capturable_distributions_unsupported

require("rsl_rl")
TensorDict = require("tensordict").TensorDict

__all__ = ["GraphedAct", "graphed_act_unsupported"]


def graphed_act_unsupported(alg: Any) -> str | None:
    """Why ``alg.act`` must stay eager (None: it can be graphed)."""
    if torch.device(alg.device).type != "cuda":
        return "a CUDA graph needs a CUDA device"
    if (reason := capturable_distributions_unsupported()) is not None:
        return reason
    if alg.actor.is_recurrent or alg.critic.is_recurrent:
        return "recurrent models (their hidden state changes per step)"
    if alg.actor is not alg._raw_actor or alg.critic is not alg._raw_critic:
        return "torch.compile'd models (torch_compile_mode)"
    return None


class GraphedAct:
    """A drop-in for ``alg.act``: ``alg.act = GraphedAct(alg)``."""

    def __init__(self, alg: Any):
        reason = graphed_act_unsupported(alg)
        if reason is not None:
            raise ValueError(f"rsl_rl's act cannot be graphed: {reason}; set agent.graph_act=false.")
        self.alg = alg
        self.device = torch.device(alg.device)
        self._eager_act = alg.act  # rsl_rl's own
        self._graph: torch.cuda.CUDAGraph | None = None
        self._key: tuple | None = None
        self._slots: list[tuple[torch.nn.Module, str]] | None = None
        self.captures = 0

    def __call__(self, obs: TensorDict) -> torch.Tensor:
        key = self._static_key(obs)
        if self._graph is None or key != self._key:
            self._capture(obs)
            self._key = key
        for name, value in obs.items():
            self._obs[name].copy_(value)
        self._graph.replay()
        transition = self.alg.transition
        transition.hidden_states = (None, None)
        transition.actions, transition.values, transition.actions_log_prob = self._outputs
        transition.distribution_params = self._distribution_params
        transition.observations = obs  # the step's own, as rsl_rl records it
        return transition.actions

    def _capture(self, obs: TensorDict) -> None:
        self._obs = TensorDict({name: value.clone() for name, value in obs.items()}, batch_size=obs.batch_size)
        with torch.random.fork_rng(devices=[self.device]):  # the warm-up's draws are not training's
            side = torch.cuda.Stream(self.device)
            side.wait_stream(torch.cuda.current_stream(self.device))
            with torch.cuda.stream(side):
                for _ in range(2):
                    with capturable_distributions():
                        self._eager_act(self._obs)
            torch.cuda.current_stream(self.device).wait_stream(side)
        graph = torch.cuda.CUDAGraph()
        try:
            with capturable_distributions(), torch.cuda.graph(graph, capture_error_mode="thread_local"):
                self._eager_act(self._obs)
        except RuntimeError as error:
            raise RuntimeError(
                f"Capturing rsl_rl's act as a CUDA graph failed ({error}). Run it eagerly: agent.graph_act=false."
            ) from error
        transition = self.alg.transition
        self._outputs = (transition.actions, transition.values, transition.actions_log_prob)
        self._distribution_params = transition.distribution_params
        self._graph = graph
        self.captures += 1

    def _static_key(self, obs: TensorDict) -> tuple:
        """What the graph reads by address or shape; a change recaptures.

        Called every step: the models' tensor slots are listed once (walking ``parameters()`` each
        step costs more than the replay's launch), then each slot's current tensor is read."""
        if self._slots is None:
            models = (self.alg.actor, self.alg.critic)
            self._slots = [
                (m, name) for model in models for m in model.modules() for name in (*m._parameters, *m._buffers)
            ]
        shapes = tuple((name, tuple(value.shape), value.dtype) for name, value in obs.items())
        tensors = (getattr(module, name) for module, name in self._slots)
        return (shapes, *(0 if t is None else t.data_ptr() for t in tensors))
