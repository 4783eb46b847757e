"""How many kernels one env step launches outside the physics, by component (CPU, reproducible).

    simlab bench ops step --task simlab/Velocity-Flat-Unitree-Go2-v0

On the GPU the part of a step outside the physics is launch-bound: each torch op or Warp launch
costs a few microseconds even inside the CUDA graph, whatever the env count. This script builds the
task with the GPU backend (MuJoCo Warp) on Warp's CPU device, so it runs anywhere, steps it, and
counts, per component (each manager's terms, the scene's assets, actuators and sensors, the env's
own bookkeeping, the physics), the torch ops that launch a kernel (``TorchDispatchMode``; views,
allocations and other metadata ops are left out) and the Warp launches (``wp.launch``). The step
body runs as the CUDA graph records it; the counts are means over ``--steps`` steps (resets happen
by mask every step, so they count in full).
"""

from __future__ import annotations

import argparse
import collections
import contextlib
import functools
import os
import sys

import torch
from torch.utils._python_dispatch import TorchDispatchMode

# Ops that launch no kernel: allocations (a graph's memory pool serves them), metadata; views are
# found by their outputs (see launches_kernel).
_NO_KERNEL = {
    "aten.empty.memory_format",
    "aten.empty_like.default",
    "aten.empty_strided.default",
    "aten.lift_fresh.default",
    "aten._to_copy.default",  # counted below only when it changes device or dtype
    "prim.device.default",
    "aten.sym_size.int",
    "aten.sym_stride.int",
    "aten.sym_numel.default",
    "aten.sym_storage_offset.default",
    "aten.is_same_size.default",
    "aten.is_nonzero.default",
}
READ_BACKS = ("aten._local_scalar_dense", "aten.nonzero", "aten.item")


def copies_from_host(func, args, kwargs) -> bool:
    """Whether a dispatched op brings host data onto the tensors' device: a tensor made from Python
    data (``torch.tensor(list, device=...)``: ``aten.lift_fresh``; on the GPU a copy from pageable
    memory, which a CUDA graph capture refuses) or a copy between a CPU and another device. The step
    is counted as it is captured, with Python list indices and numbers written by indexing turned into
    device tensors (:class:`~simlab.envs.utils.cuda_graph.DeviceListIndices`), so those do not count."""
    name = str(func)
    if name == "aten.lift_fresh.default":
        return True
    if name == "aten._to_copy.default":
        return _changes_device_or_dtype(args[0], {"device": kwargs.get("device", args[0].device)})
    if name.startswith("aten.copy_"):
        return len({t.device.type for t in _tensors(args[:2])}) > 1
    return False


def launches_kernel(func, args, kwargs, outputs) -> bool:
    """Whether a dispatched aten op runs a kernel (on the GPU: a launch): not a view or a
    metadata op (whose outputs all alias its inputs without writing them), nor an allocation."""
    name = str(func)
    if name in _NO_KERNEL:
        return name == "aten._to_copy.default" and _changes_device_or_dtype(args[0], kwargs)
    if func._schema.is_mutable:  # in-place and out= ops write memory
        return True
    inputs = {t.untyped_storage().data_ptr() for t in _tensors((args, kwargs))}
    produced = _tensors(outputs)
    if not produced:  # a number or a dtype: only a read of a device value costs a transfer
        return name.startswith(READ_BACKS)
    return not all(t.untyped_storage().data_ptr() in inputs for t in produced)


def _changes_device_or_dtype(src: torch.Tensor, kwargs) -> bool:
    device = torch.device(kwargs.get("device", src.device))
    return kwargs.get("dtype", src.dtype) != src.dtype or device != src.device


def _tensors(value) -> list[torch.Tensor]:
    if isinstance(value, torch.Tensor):
        return [value]
    if isinstance(value, dict):
        value = list(value.values())
    if isinstance(value, (list, tuple)):
        return [t for item in value for t in _tensors(item)]
    return []


class LaunchCounter(TorchDispatchMode):
    """Counts kernel-launching torch ops and Warp launches per component label.

    ``scope(label)`` sets the component that ops inside it count for; scopes nest and the innermost
    wins, so a term's ops count for the term, not for the manager that called it.
    """

    def __init__(self):
        super().__init__()
        self.labels: list[str] = ["env.step (outside the step body)"]
        self.torch_ops: collections.Counter[str] = collections.Counter()
        self.warp_launches: collections.Counter[str] = collections.Counter()
        self.read_backs: collections.Counter[str] = collections.Counter()
        self.host_copies: collections.Counter[str] = collections.Counter()
        self.op_names: dict[str, collections.Counter[str]] = collections.defaultdict(collections.Counter)
        self.active = False
        self.warp_launched = 0  # every Warp launch, counted or not
        self._in_graph_run = False

    def __torch_dispatch__(self, func, types, args=(), kwargs=None):
        kwargs = kwargs or {}
        outputs = func(*args, **kwargs)
        if self.active and copies_from_host(func, args, kwargs):
            self.host_copies[self.labels[-1]] += 1
        if self.active and launches_kernel(func, args, kwargs, outputs):
            label = self.labels[-1]
            self.torch_ops[label] += 1
            self.op_names[label][str(func)] += 1
            if str(func).startswith(READ_BACKS):
                self.read_backs[label] += 1
        return outputs

    @contextlib.contextmanager
    def scope(self, label: str):
        self.labels.append(label)
        try:
            yield
        finally:
            self.labels.pop()

    def wrap(self, owner, attr: str, label: str) -> None:
        """Count what ``owner.attr(...)`` runs for ``label`` (patches the instance attribute)."""
        original = getattr(owner, attr)

        @functools.wraps(original)
        def counted(*args, **kwargs):
            with self.scope(label):
                return original(*args, **kwargs)

        # a class term's marks are class attributes, which functools.wraps does not copy: an event
        # term that takes a bool mask would otherwise be handed env ids
        counted.takes_env_mask = getattr(original, "takes_env_mask", False)
        setattr(owner, attr, counted)

    def count_warp_launches(self, module) -> None:
        """Count ``module.launch`` / ``launch_tiled`` calls (Warp's kernel launches) for the current label."""
        for name in ("launch", "launch_tiled"):
            original = getattr(module, name, None)
            if original is None:
                continue

            def counted(*args, _original=original, **kwargs):
                self.warp_launched += 1
                if self.active and not self._in_graph_run:
                    self.warp_launches[self.labels[-1]] += 1
                return _original(*args, **kwargs)

            setattr(module, name, counted)

    def count_graph_replays(self, physics) -> None:
        """The physics backend replays Warp graphs (``_run(key, body)``, captured on first use):
        count each replay as the launches its capture recorded."""
        original = physics._run
        recorded: dict = {}

        def run(key, body):
            before = self.warp_launched
            self._in_graph_run = True
            try:
                original(key, body)
            finally:
                self._in_graph_run = False
            if self.warp_launched > before:  # captured (or run eagerly) by this call
                recorded[key] = self.warp_launched - before
            if self.active:
                self.warp_launches[self.labels[-1]] += recorded.get(key, 0)

        physics._run = run


def instrument(env, counter: LaunchCounter) -> None:
    """Label every component of a manager-based env's step."""
    wrap = counter.wrap
    wrap(env, "_step_body", "env (step body's own ops)")
    wrap(env, "_restart_diverged", "env (diverged worlds)")
    wrap(env.sim, "step", "physics")
    physics = env.sim.physics
    if hasattr(physics, "_graphs"):  # MuJoCo Warp's graphs
        counter.count_graph_replays(physics)
        physics._graphs.clear()  # captured again under the counter (some were captured while building the env)
    wrap(physics, "forward", "physics forward (derived quantities the MDP reads)")
    if hasattr(physics, "_kinematics"):
        wrap(physics, "_kinematics", "physics kinematics (body poses the MDP reads)")
    wrap(physics, "reset", "physics reset")
    wrap(physics, "restart", "env (diverged worlds)")
    # scene: assets, their actuators, sensors
    scene = env.scene
    entities = {**scene.articulations, **scene.rigid_objects, **scene.rigid_object_collections, **scene.sensors}
    for name, entity in entities.items():
        for method in ("write_data_to_sim", "update", "reset"):
            if hasattr(entity, method):
                wrap(entity, method, f"scene/{name}.{method}")
        for group, actuator in getattr(entity, "actuators", {}).items():
            wrap(actuator, "compute", f"actuators/{name}.{group}")
            wrap(actuator, "reset", f"actuators/{name}.{group}.reset")
    # a direct env's own hooks (DirectRLEnv)
    for hook in ("_pre_physics_step", "_apply_action", "_get_dones", "_get_rewards", "_reset_mask", "_observations"):
        if hasattr(env, hook) and not hasattr(env, "action_manager"):
            wrap(env, hook, f"task/{hook.lstrip('_')}")
    # managers and their terms
    for manager_name in ("action", "observation", "reward", "termination", "command", "event", "curriculum"):
        manager = getattr(env, f"{manager_name}_manager", None)
        if manager is None:
            continue
        for method in ("compute", "reset", "apply", "process_action", "apply_action"):
            if hasattr(manager, method):
                wrap(manager, method, f"{manager_name}s (manager)")
        if manager_name == "action":
            for term_name, term in zip(manager.active_terms, manager._terms.values()):
                wrap(term, "process_actions", f"actions/{term_name}")
                wrap(term, "apply_actions", f"actions/{term_name}")
                if hasattr(term, "reset"):
                    wrap(term, "reset", f"actions/{term_name}.reset")
        elif manager_name == "command":
            for term_name in manager.active_terms:
                term = manager.get_term(term_name)
                wrap(term, "compute", f"commands/{term_name}")
                wrap(term, "reset", f"commands/{term_name}.reset")
        elif manager_name == "observation":
            for group, names in manager.active_terms.items():
                for term_name in names:
                    cfg = manager.get_term_cfg(group, term_name)
                    wrap(cfg, "func", f"observations/{term_name}")
        elif manager_name == "event":
            for mode, names in manager.active_terms.items():
                for term_name in names:
                    wrap(manager.get_term_cfg(term_name), "func", f"events/{term_name} ({mode})")
        else:
            for term_name in manager.active_terms:
                wrap(manager.get_term_cfg(term_name), "func", f"{manager_name}s/{term_name}")


def make_env(task: str, num_envs: int, seed: int, engine: str = "mujoco_warp"):
    import gymnasium as gym

    import simlab.tasks  # noqa: F401 - registers the tasks
    from simlab.tasks.utils import parse_env_cfg

    cfg = parse_env_cfg(task, device="cpu", num_envs=num_envs)
    cfg.sim.engine = engine  # mujoco_warp: the GPU backend, on Warp's CPU device
    cfg.seed = seed
    return gym.make(task, cfg=cfg).unwrapped


def count(task: str, num_envs: int, steps: int, seed: int = 0, engine: str = "mujoco_warp") -> LaunchCounter:
    from simlab.envs.utils.cuda_graph import DeviceListIndices

    env = make_env(task, num_envs, seed, engine)
    counter = LaunchCounter()
    if engine == "mujoco_warp":
        import warp as wp

        counter.count_warp_launches(wp)
    instrument(env, counter)
    torch.manual_seed(seed)
    env.reset()
    action_dim = (
        env.action_manager.total_action_dim if hasattr(env, "action_manager") else env.single_action_space.shape[-1]
    )
    actions = torch.rand(env.num_envs, action_dim) * 2 - 1
    # as the capture runs it: list indices and indexed writes of numbers through device tensors
    list_indices = DeviceListIndices(torch.device(env.device), {})
    with torch.inference_mode(), list_indices, counter:
        for _ in range(3):  # warm-up: lazy buffers, index caches, compiled kernels
            env.step(actions)
        counter.active = True
        for _ in range(steps):
            env.step(actions)
        counter.active = False
    env.close()
    return counter


def report(counter: LaunchCounter, steps: int, top_ops: int = 0) -> str:
    labels = sorted(set(counter.torch_ops) | set(counter.warp_launches))
    physics = {label for label in labels if label == "physics"}
    rows = []
    for label in labels:
        torch_n = counter.torch_ops[label] / steps
        warp_n = counter.warp_launches[label] / steps
        rows.append((label, torch_n, warp_n))
    rows.sort(key=lambda row: (row[0] in physics, -(row[1] + row[2])))
    width = max(len(label) for label, *_ in rows) if rows else 10
    lines = [f"{'component':<{width}}  {'torch':>7}  {'warp':>6}  {'total':>7}"]
    outside_torch = outside_warp = 0.0
    for label, torch_n, warp_n in rows:
        lines.append(f"{label:<{width}}  {torch_n:7.1f}  {warp_n:6.1f}  {torch_n + warp_n:7.1f}")
        if label not in physics:
            outside_torch += torch_n
            outside_warp += warp_n
        if top_ops:
            for op, n in counter.op_names[label].most_common(top_ops):
                lines.append(f"{'':<{width}}    {n / steps:6.1f}  {op}")
    read_backs = sum(counter.read_backs.values()) / steps
    host_copies = sum(counter.host_copies.values()) / steps
    lines.append(
        f"{'outside physics':<{width}}  {outside_torch:7.1f}  {outside_warp:6.1f}  {outside_torch + outside_warp:7.1f}"
        f"   (host read-backs: {read_backs:.1f}, copies from the host: {host_copies:.1f})"
    )
    for label, n in sorted(counter.host_copies.items()):
        lines.append(f"  copies from the host in {label}: {n / steps:.1f}")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(
        prog="simlab bench ops step", description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("--task", default="simlab/Velocity-Flat-Unitree-Go2-v0")
    parser.add_argument("--num_envs", type=int, default=8)
    parser.add_argument("--steps", type=int, default=5)
    parser.add_argument("--ops", type=int, default=0, help="also list each component's N most frequent ops")
    parser.add_argument(
        "--engine",
        default="mujoco_warp",
        choices=("mujoco_warp", "mujoco"),
        help="mujoco_warp: the GPU backend on Warp's CPU device (counts its Warp launches too); mujoco: the "
        "CPU backend (the same torch ops outside the physics, no Warp)",
    )
    args = parser.parse_args(argv)
    os.environ.setdefault("MUJOCO_GL", "osmesa")
    counter = count(args.task, args.num_envs, args.steps, engine=args.engine)
    print(
        f"{args.task}, {args.num_envs} envs, engine {args.engine}: kernels launched per env step"
        f" (means over {args.steps} steps)"
    )
    print(report(counter, args.steps, args.ops))
    sys.stdout.flush()


if __name__ == "__main__":
    main()
