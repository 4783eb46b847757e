"""rsl_rl's PPO update without a host read per mini-batch, replayed as one CUDA graph on the GPU.

rsl_rl's ``PPO.update`` reads four values back to the host in every mini-batch (the KL test of the
adaptive learning rate and three loss logs) and launches a few hundred small kernels each; for a
cartpole-sized network that host work, not the GPU, sets the update's time. :class:`FastPPOUpdate`
runs the same update on the same rsl_rl objects (its actor, critic, storage, optimizer and
hyperparameters) with the per-mini-batch decisions kept on the device:

- the adaptive learning rate lives in a 0-d tensor that the optimizer reads (torch's Adam takes a
  tensor ``lr``); each mini-batch's KL test updates it with ``torch.where`` instead of ``if``;
- the losses are summed on the device; the sums and the final learning rate come back in one read
  at the end of the update;
- on CUDA the whole update (all epochs and mini-batches) is captured once as a CUDA graph and
  replayed each iteration; on the CPU the same code runs eagerly.

The mini-batch indices are drawn as rsl_rl draws them (one ``randperm`` per update, shared by the
epochs), so with the same random state both give the same update up to float rounding
(``tests/test_rsl_rl_fast_update.py`` checks it against rsl_rl's own ``PPO.update``).

Configurations it does not cover (recurrent models, RND, symmetry, multi-GPU, compiled models,
optimizers other than Adam / AdamW, a subclass with its own ``update``) keep rsl_rl's update:
:func:`fast_update_unsupported` says why.
"""

from __future__ import annotations

import contextlib
import warnings
from collections.abc import Iterator
from typing import Any

import torch
from torch import nn

from simlab.rl.utils import require
from simlab.utils.versions import release_mismatch

from .capturable import capturable_distributions, capturable_distributions_unsupported

require("rsl_rl")
TensorDict = require("tensordict").TensorDict
from rsl_rl.algorithms import PPO  # noqa: E402

__all__ = ["FastPPOUpdate", "fast_update_unsupported"]

_LOSSES = ("value", "surrogate", "entropy")


def rsl_rl_version_mismatch() -> str | None:
    """Why the installed rsl-rl-lib is not the release this copy of ``PPO.update`` follows; None when it is."""
    mismatch = release_mismatch("rsl-rl-lib")
    return None if mismatch is None else f"{mismatch}: simlab's fast update copies that release's PPO.update"


def fast_update_unsupported(alg: Any) -> str | None:
    """Why ``alg`` must keep rsl_rl's own update (None: the fast update covers it)."""
    mismatch = rsl_rl_version_mismatch()
    if mismatch is not None:
        return mismatch
    if torch.device(alg.device).type == "cuda" and (reason := capturable_distributions_unsupported()):
        return reason
    if not isinstance(alg, PPO) or type(alg).update is not PPO.update:
        return f"the algorithm {type(alg).__name__} has its own update"
    if alg.actor.is_recurrent or alg.critic.is_recurrent:
        return "recurrent models"
    if alg.rnd is not None:
        return "random network distillation (rnd_cfg)"
    if alg.symmetry is not None:
        return "symmetry augmentation (symmetry_cfg)"
    if alg.is_multi_gpu:
        return "multi-GPU training"
    if alg.actor is not alg._raw_actor or alg.critic is not alg._raw_critic:
        return "torch.compile'd models (torch_compile_mode)"
    if type(alg.optimizer) not in (torch.optim.Adam, torch.optim.AdamW):
        return f"the optimizer {type(alg.optimizer).__name__} (Adam and AdamW take a tensor learning rate)"
    return None


class FastPPOUpdate:
    """A drop-in for ``alg.update``: ``alg.update = FastPPOUpdate(alg)``.

    Args:
        alg: rsl_rl's PPO, as the runner built it.
        cuda_graph: capture the update as a CUDA graph (default: when ``alg`` is on a CUDA device).
    """

    def __init__(self, alg: PPO, cuda_graph: bool | None = None):
        reason = fast_update_unsupported(alg)
        if reason is not None:
            raise ValueError(f"The fast PPO update does not cover {reason}; set agent.fast_update=false.")
        self.alg = alg
        self.device = torch.device(alg.device)
        if cuda_graph is None:
            cuda_graph = self.device.type == "cuda"
        if cuda_graph and self.device.type != "cuda":
            raise ValueError(f"A CUDA graph needs a CUDA device; the learner is on {alg.device}.")
        self.cuda_graph = cuda_graph
        self._lr = torch.tensor(float(alg.learning_rate), device=self.device)
        self._lr_written = float(alg.learning_rate)  # what self._lr holds, without reading it back
        self._sums = torch.zeros(len(_LOSSES), device=self.device)
        self._graph: torch.cuda.CUDAGraph | None = None
        self._graph_key: tuple[int, ...] | None = None
        self.captures = 0  # CUDA graph captures so far (1 in a normal run)

    @property
    def _adaptive(self) -> bool:
        return self.alg.desired_kl is not None and self.alg.schedule == "adaptive"

    # -- the update ------------------------------------------------------------------------------

    def __call__(self) -> dict[str, float]:
        alg, storage = self.alg, self.alg.storage
        if float(alg.learning_rate) != self._lr_written:  # set from outside, e.g. loading a checkpoint
            self._lr.fill_(float(alg.learning_rate))
        batch_size = storage.num_envs * storage.num_transitions_per_env
        mini_batch_size = batch_size // alg.num_mini_batches
        # the draw rsl_rl's mini_batch_generator makes, once per update and shared by the epochs
        indices = torch.randperm(alg.num_mini_batches * mini_batch_size, requires_grad=False, device=self.device)
        if self.cuda_graph:
            self._replay(indices, mini_batch_size)
        else:
            with self._optimizer_reads_lr_tensor():
                self._sums.zero_()
                self._run(self._flat_batch(storage.advantages), indices, mini_batch_size)
        # the one read back of the update: the loss sums and the adapted learning rate
        *sums, learning_rate = torch.cat([self._sums, self._lr.view(1)]).tolist()
        if self._adaptive:  # else the rate stays the float it was (the tensor holds it in float32)
            self._set_learning_rate(learning_rate)
        with self._buffers_kept_in_place():  # rsl_rl's normalizer replaces its buffers; the graph reads them
            obs = storage.observations.flatten(0, 1)
            alg.actor.update_normalization(obs)
            alg.critic.update_normalization(obs)
        storage.clear()
        updates = alg.num_learning_epochs * alg.num_mini_batches
        return {name: total / updates for name, total in zip(_LOSSES, sums)}

    def _run(self, batch: dict[str, Any], indices: torch.Tensor, mini_batch_size: int) -> None:
        for _ in range(self.alg.num_learning_epochs):
            for i in range(self.alg.num_mini_batches):
                self._mini_batch_step(batch, indices[i * mini_batch_size : (i + 1) * mini_batch_size])

    def _mini_batch_step(self, batch: dict[str, Any], idx: torch.Tensor) -> None:
        """One mini-batch of rsl_rl's ``PPO.update`` (feed-forward models), with no host read."""
        alg = self.alg
        observations = TensorDict({k: v[idx] for k, v in batch["observations"].items()}, batch_size=[idx.shape[0]])
        actions, old_values, returns = batch["actions"][idx], batch["values"][idx], batch["returns"][idx]
        advantages, old_log_prob = batch["advantages"][idx], batch["actions_log_prob"][idx]
        old_distribution_params = tuple(p[idx] for p in batch["distribution_params"])
        if alg.normalize_advantage_per_mini_batch:
            with torch.no_grad():
                advantages = (advantages - advantages.mean()) / (advantages.std() + 1e-8)

        with torch.autocast(self.device.type, enabled=alg.use_mixed_precision, dtype=torch.bfloat16):
            alg.actor(observations, stochastic_output=True)  # as rsl_rl calls it: sets the distribution
            log_prob = alg.actor.get_output_log_prob(actions)
            values = alg.critic(observations)
            distribution_params = alg.actor.output_distribution_params
            entropy = alg.actor.output_entropy

            if self._adaptive:
                with torch.no_grad():
                    kl = alg.actor.get_kl_divergence(old_distribution_params, distribution_params).mean()
                    lower = torch.clamp(self._lr / 1.5, min=1e-5)
                    higher = torch.clamp(self._lr * 1.5, max=1e-2)
                    raise_lr = (kl < alg.desired_kl / 2.0) & (kl > 0.0)
                    new_lr = torch.where(kl > alg.desired_kl * 2.0, lower, torch.where(raise_lr, higher, self._lr))
                    self._lr.copy_(new_lr)

            ratio = torch.exp(log_prob - torch.squeeze(old_log_prob))
            advantages = torch.squeeze(advantages)
            surrogate = -advantages * ratio
            surrogate_clipped = -advantages * torch.clamp(ratio, 1.0 - alg.clip_param, 1.0 + alg.clip_param)
            surrogate_loss = torch.max(surrogate, surrogate_clipped).mean()
            if alg.use_clipped_value_loss:
                value_clipped = old_values + (values - old_values).clamp(-alg.clip_param, alg.clip_param)
                value_losses = (values - returns).pow(2)
                value_losses_clipped = (value_clipped - returns).pow(2)
                value_loss = torch.max(value_losses, value_losses_clipped).mean()
            else:
                value_loss = (returns - values).pow(2).mean()
            entropy_mean = entropy.mean()
            loss = surrogate_loss + alg.value_loss_coef * value_loss - alg.entropy_coef * entropy_mean

        alg.optimizer.zero_grad()
        loss.backward()
        nn.utils.clip_grad_norm_(alg.actor.parameters(), alg.max_grad_norm)
        nn.utils.clip_grad_norm_(alg.critic.parameters(), alg.max_grad_norm)
        alg.optimizer.step()
        self._sums.add_(torch.stack([value_loss, surrogate_loss, entropy_mean]).detach().float())

    def _flat_batch(self, advantages: torch.Tensor) -> dict[str, Any]:
        """The storage's tensors with (steps, envs) flattened: views, so a graph reads each new rollout."""
        st = self.alg.storage
        return {
            "observations": {k: v.flatten(0, 1) for k, v in st.observations.items()},
            "actions": st.actions.flatten(0, 1),
            "values": st.values.flatten(0, 1),
            "returns": st.returns.flatten(0, 1),
            "actions_log_prob": st.actions_log_prob.flatten(0, 1),
            "advantages": advantages.flatten(0, 1),
            "distribution_params": tuple(p.flatten(0, 1) for p in st.distribution_params),
        }

    def _set_learning_rate(self, learning_rate: float) -> None:
        self.alg.learning_rate = learning_rate
        self._lr_written = learning_rate
        for group in self.alg.optimizer.param_groups:
            group["lr"] = learning_rate

    # -- the CUDA graph --------------------------------------------------------------------------

    def _replay(self, indices: torch.Tensor, mini_batch_size: int) -> None:
        key = self._static_key()
        if self._graph is None or key != self._graph_key:
            self._capture(indices, mini_batch_size)
            self._graph_key = self._static_key()
        # compute_returns makes a new advantages tensor each iteration: copy it where the graph reads
        self._advantages.copy_(self.alg.storage.advantages)
        self._indices.copy_(indices)
        self._graph.replay()

    def _capture(self, indices: torch.Tensor, mini_batch_size: int) -> None:
        """Capture one whole update; a warm-up first creates the optimizer's state, then is undone."""
        self._advantages = self.alg.storage.advantages.clone()
        self._indices = indices.clone()
        batch = self._flat_batch(self._advantages)
        with self._optimizer_reads_lr_tensor(), self._undone():
            side = torch.cuda.Stream(self.device)
            side.wait_stream(torch.cuda.current_stream(self.device))
            with torch.cuda.stream(side), warnings.catch_warnings():
                warnings.filterwarnings("ignore", message=".*capturable=True.*")  # the warm-up runs uncaptured
                for _ in range(2):
                    self._mini_batch_step(batch, self._indices[:mini_batch_size])
            torch.cuda.current_stream(self.device).wait_stream(side)
        graph = torch.cuda.CUDAGraph()
        self.alg.optimizer.zero_grad()
        try:
            with (
                self._optimizer_reads_lr_tensor(),
                capturable_distributions(),
                torch.cuda.graph(graph, capture_error_mode="thread_local"),
            ):
                self._sums.zero_()
                self._run(batch, self._indices, mini_batch_size)
        except RuntimeError as error:
            raise RuntimeError(
                f"Capturing the PPO update as a CUDA graph failed ({error}). Train with rsl_rl's own update: "
                "agent.fast_update=false."
            ) from error
        self._graph = graph
        self.captures += 1

    def _static_key(self) -> tuple[int, ...]:
        """Addresses the graph reads or writes; a change (a new buffer, a loaded optimizer) recaptures."""
        alg, st = self.alg, self.alg.storage
        tensors = [*st.observations.values(), st.actions, st.values, st.returns, st.actions_log_prob]
        tensors += list(st.distribution_params)
        tensors += list(alg.actor.parameters()) + list(alg.critic.parameters())
        tensors += list(alg.actor.buffers()) + list(alg.critic.buffers())
        tensors += [t for state in alg.optimizer.state.values() for t in state.values() if torch.is_tensor(t)]
        return (st.advantages.shape[0] * st.advantages.shape[1], *(t.data_ptr() for t in tensors))

    def _prepare_optimizer_state(self) -> None:
        """Adam's step counters on the device, as a captured (capturable) step needs them."""
        for state in self.alg.optimizer.state.values():
            if "step" in state and state["step"].device != self.device:
                state["step"] = state["step"].to(self.device, torch.float32)

    @contextlib.contextmanager
    def _undone(self) -> Iterator[None]:
        """Put back the weights, optimizer state, learning rate, loss sums and random state after the block."""
        alg = self.alg
        params = [p for group in alg.optimizer.param_groups for p in group["params"]]
        saved_params = [p.detach().clone() for p in params]
        saved_state = {
            p: {k: v.clone() for k, v in state.items() if torch.is_tensor(v)}
            for p, state in alg.optimizer.state.items()
        }
        saved_lr, saved_sums = self._lr.clone(), self._sums.clone()
        with torch.random.fork_rng(devices=[self.device]):
            yield
        with torch.no_grad():
            for p, saved in zip(params, saved_params):
                p.copy_(saved)
            for p, state in alg.optimizer.state.items():
                for k, v in state.items():
                    if not torch.is_tensor(v):
                        continue
                    if p in saved_state and k in saved_state[p]:
                        v.copy_(saved_state[p][k])
                    else:  # state the warm-up created starts from zero, as Adam's own first step has it
                        v.zero_()
            self._lr.copy_(saved_lr)
            self._sums.copy_(saved_sums)
        alg.optimizer.zero_grad()

    @contextlib.contextmanager
    def _optimizer_reads_lr_tensor(self) -> Iterator[None]:
        """The optimizer takes its learning rate from ``self._lr`` (capturable on CUDA) inside the block."""
        groups = self.alg.optimizer.param_groups
        saved = [(g["lr"], g.get("capturable", False)) for g in groups]
        for g in groups:
            g["lr"] = self._lr
            if self.device.type == "cuda":
                g["capturable"] = True  # a tensor lr with foreach needs it; the steps stay on the device
        if self.device.type == "cuda":
            self._prepare_optimizer_state()
        try:
            yield
        finally:
            for g, (lr, capturable) in zip(groups, saved):
                g["lr"], g["capturable"] = lr, capturable

    @contextlib.contextmanager
    def _buffers_kept_in_place(self) -> Iterator[None]:
        """Buffers the block replaces (rsl_rl's normalizer assigns a new ``_std``) go back into the old tensors."""
        modules = [m for model in (self.alg.actor, self.alg.critic) for m in model.modules()]
        before = [(m, name, t) for m in modules for name, t in m._buffers.items() if t is not None]
        yield
        with torch.no_grad():
            for module, name, old in before:
                new = module._buffers.get(name)
                if new is not None and new is not old and new.shape == old.shape:
                    old.copy_(new)
                    module._buffers[name] = old
