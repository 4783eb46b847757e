"""rsl_rl's per-step bookkeeping in the rollout, replayed as one CUDA graph per step of the rollout.

After each env step, rsl_rl's ``PPO.process_env_step`` bootstraps the time-outs' values and copies
the transition into its storage (26 small torch ops: selects, views, copies), and simlab's logger
adds the rewards to the running episode sums (7 ops). At a few thousand envs each op costs a kernel
launch from Python, not GPU work. :class:`FastRolloutStep` runs both, rsl_rl's own code and the
logger's, as one body; on CUDA it captures that body once per storage row (rsl_rl writes row
``storage.step``, a Python int, so each row is its own graph) and then, each step, copies the
step's rewards, dones and time-outs into the graphs' inputs and replays one graph.

The graphs read the policy's inputs and outputs where :class:`~simlab.rl.rsl_rl.graphed_act.GraphedAct`
keeps them (its graph's own buffers, which hold this step's values when the env step returns), so
they need the graphed act. They read the storage's, the act graph's and the logger's buffers by
address; if one is replaced they are captured again. Rows are captured in the second rollout, after
each ran once eagerly. The same values reach the storage and the logger as with rsl_rl's own loop:
the body is the same ops in the same order.
"""

from __future__ import annotations

from typing import Any

import torch

from simlab.rl.utils import require
from simlab.utils.cuda import gc_paused
from simlab.utils.errors import describe

require("rsl_rl")
from rsl_rl.algorithms import PPO  # noqa: E402

__all__ = ["FastRolloutStep", "fast_rollout_unsupported"]


def fast_rollout_unsupported(alg: Any) -> str | None:
    """Why the rollout step must stay rsl_rl's own (None: simlab's covers it)."""
    if not isinstance(alg, PPO) or type(alg).process_env_step is not PPO.process_env_step:
        return f"an algorithm with its own process_env_step ({type(alg).__name__})"
    if alg.rnd is not None:
        return "RND (its intrinsic rewards are logged per step)"
    if alg.actor.is_recurrent or alg.critic.is_recurrent:
        return "recurrent models (their hidden states are stored per step)"
    return None


class FastRolloutStep:
    """A drop-in for ``alg.process_env_step`` that also keeps ``logger``'s episode sums.

    Args:
        alg: rsl_rl's PPO.
        logger: simlab's ``_ProgressLogger`` whose per-step episode sums this step keeps (its own
            ``process_env_step`` then only collects the env's logs), or None.
        cuda_graph: capture and replay the step (needs CUDA and ``alg.act`` graphed); False runs
            the same body eagerly.
    """

    def __init__(self, alg: Any, logger: Any | None = None, cuda_graph: bool | None = None):
        reason = fast_rollout_unsupported(alg)
        if reason is not None:
            raise ValueError(f"simlab's rollout step does not cover {reason}; set agent.fast_rollout=false.")
        self.alg = alg
        self.logger = logger
        self._eager_step = alg.process_env_step  # rsl_rl's own
        self._act = alg.act  # simlab's GraphedAct where the policy is graphed (read by the graphs)
        if cuda_graph is None:
            cuda_graph = torch.device(alg.device).type == "cuda"
        if cuda_graph and torch.device(alg.device).type != "cuda":
            raise ValueError("a CUDA graph of the rollout step needs a CUDA device")
        self.cuda_graph = cuda_graph
        self.eager_reason: str | None = None
        self.captures = 0
        self._graphs: dict[int, torch.cuda.CUDAGraph] = {}
        self._ran_eagerly: set[int] = set()
        self._key: tuple | None = None
        self._rows: list[tuple[torch.Tensor, torch.Tensor, torch.Tensor]] = []
        if logger is not None:
            logger.episode_sums_in_rollout = True

    def __call__(self, obs: Any, rewards: torch.Tensor, dones: torch.Tensor, extras: dict) -> None:
        storage = self.alg.storage
        row = storage.step
        if row >= storage.num_transitions_per_env:
            raise OverflowError("Rollout buffer overflow! You should call clear() before adding new transitions.")
        if not self._can_replay(row):
            self._ran_eagerly.add(row)
            self._body(obs, rewards, dones, extras, row)
            return
        key = self._static_key(extras)
        if key != self._key:
            self._new_inputs(rewards, dones, extras)
            self._key = key
        if row not in self._graphs and not self._capture(row):
            self._body(obs, rewards, dones, extras, row)
            return
        self._rewards.copy_(rewards)
        self._dones.copy_(dones)
        if self._time_outs is not None:
            self._time_outs.copy_(extras["time_outs"])
        self._graphs[row].replay()
        # what the body does on the host besides its kernels
        storage.step = row + 1
        self.alg.transition.clear()
        if self.logger is not None:
            self.logger._finished.append(self._logger_row(row))

    # -- the body: rsl_rl's process_env_step, then the logger's episode sums ----------------------------

    def _body(self, obs: Any, rewards: torch.Tensor, dones: torch.Tensor, extras: dict, row: int) -> None:
        self._eager_step(obs, rewards, dones, extras)
        if self.logger is not None:
            self.logger.add_episode_step(rewards, dones, into=self._logger_row(row))

    def _logger_row(self, row: int) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor]:
        """Row ``row`` of the (steps, envs) buffers the logger's finished-episode flags, returns and
        lengths go into (kept until the logger reads them at the iteration's end)."""
        steps = self.alg.storage.num_transitions_per_env
        sums, lengths = self.logger.cur_reward_sum, self.logger.cur_episode_length
        if not self._rows or self._rows[0][1].shape != sums.shape:
            done = torch.zeros((steps, *sums.shape), dtype=torch.bool, device=sums.device)
            returns = torch.zeros((steps, *sums.shape), dtype=sums.dtype, device=sums.device)
            lengths = torch.zeros((steps, *lengths.shape), dtype=lengths.dtype, device=lengths.device)
            self._rows = list(zip(done, returns, lengths))
        return self._rows[row]

    # -- the graphs ------------------------------------------------------------------------------------

    def _can_replay(self, row: int) -> bool:
        act = self._act
        return (
            self.cuda_graph
            and row in self._ran_eagerly  # the row ran once eagerly: the storage's lazy buffers exist
            and getattr(act, "_graph", None) is not None  # simlab's GraphedAct, captured
            and self.alg.transition.actions is act._outputs[0]  # and it ran this step
        )

    def _new_inputs(self, rewards: torch.Tensor, dones: torch.Tensor, extras: dict) -> None:
        self._graphs.clear()
        self._pool = torch.cuda.graph_pool_handle()
        self._rewards, self._dones = rewards.clone(), dones.clone()
        self._time_outs = extras["time_outs"].clone() if "time_outs" in extras else None

    def _capture(self, row: int) -> bool:
        """Record row ``row``'s body and undo its host side effects (the replay that follows does
        them). False if the capture failed: then nothing happened and the step runs eagerly from now on."""
        alg, act = self.alg, self._act
        transition = alg.transition
        before = dict(vars(transition))
        transition.observations = act._obs  # the act graph's input: holds this step's observations
        extras = {} if self._time_outs is None else {"time_outs": self._time_outs}
        finished = len(self.logger._finished) if self.logger is not None else 0
        graph = torch.cuda.CUDAGraph()
        try:
            with (
                torch.cuda.device(torch.device(alg.device)),
                gc_paused(),
                torch.cuda.graph(graph, pool=self._pool, capture_error_mode="thread_local"),
            ):
                self._body(act._obs, self._rewards, self._dones, extras, row)
        except Exception as error:  # noqa: BLE001 - a capture records kernels and runs none: nothing to undo on the device
            self.cuda_graph = False
            self._graphs.clear()
            self.eager_reason = f"capture failed: {describe(error)}"
            print(f"[simlab] CUDA-graph capture of the rollout step failed, running it eagerly: {self.eager_reason}")
            captured = False
        else:
            self._graphs[row] = graph
            self.captures += 1
            captured = True
        alg.storage.step = row
        vars(transition).update(before)
        if self.logger is not None:
            del self.logger._finished[finished:]
        return captured

    def _static_key(self, extras: dict) -> tuple:
        """What the graphs read by address, shape or value; a change captures them again."""
        alg, act, storage = self.alg, self._act, self.alg.storage
        tensors = [
            *act._obs.values(),
            *act._outputs,
            *act._distribution_params,
            *storage.observations.values(),
            storage.actions,
            storage.rewards,
            storage.dones,
            storage.values,
            storage.actions_log_prob,
            *storage.distribution_params,
        ]
        if self.logger is not None:
            tensors += [self.logger.cur_reward_sum, self.logger.cur_episode_length, *self._logger_row(0)]
        return ("time_outs" in extras, alg.gamma, act.captures, *(t.data_ptr() for t in tensors))
