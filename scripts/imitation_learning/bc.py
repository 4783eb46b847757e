"""Behaviour cloning from recorded demonstrations: an MLP from policy observations to actions (simlab's
stand-in for Isaac Lab's robomimic BC, which simlab does not depend on), judged by the task's criterion.

``train`` reads an HDF5 dataset that simlab's recorder wrote (``simlab record``, or the stack state
machine's ``--dataset_file``): per step the policy observation terms ``obs/<term>`` and the
``actions`` (or, with ``--actions_key clean_actions``, the state machine's actions before its noise).
It fits ``actions = mlp((obs - mean) / std)`` (actions normalized alike, the leading ones as offsets
from the end effector on IK-Abs: :class:`BCPolicy`) by mean squared error, with the settings of the
recipe the demonstrations' task registers (``bc_cfg_entry_point``) unless given, and saves the weights
with the observation terms, their statistics and the task's name in one ``torch.save`` file
(tensors, strings and numbers only: ``torch.load(weights_only=True)`` reads it). ``play`` steps the
task with that policy and judges the run as ``simlab bench solve`` and make_pretrained judge a
checkpoint: the criterion the task registers, over a rollout of ``simlab play`` (seeded reset).

    python scripts/environments/state_machine/stack_cube_sm.py --num_envs 50 --headless --device cpu \\
        --seed 3 --noise 0.005 --dataset_file logs/demos/stack.hdf5 --num_demos 1000
    python scripts/imitation_learning/bc.py train --dataset_file logs/demos/stack.hdf5 --out logs/bc/stack.pt
    python scripts/imitation_learning/bc.py play --checkpoint logs/bc/stack.pt --num_envs 32

The policy and its file are :mod:`simlab.rl.bc`'s: ``simlab play --library bc --checkpoint`` plays it
too, and ``scripts/make_pretrained.py --library bc --checkpoint`` ships it (docs/manipulation.md gives
what these measured).
"""

from __future__ import annotations

import argparse
import sys
import time

import torch

from simlab.rl.bc import BCAgentCfg, BCPolicy, load_bc_policy, save_bc_policy

OBS_TERMS = tuple(BCAgentCfg().obs_terms)
"""The observation terms Isaac Lab's robomimic configs of the stack task feed BC."""


def load_demos(
    path: str, terms: list[str], actions_key: str = "actions"
) -> tuple[torch.Tensor, torch.Tensor, str | None]:
    """(steps, obs) observations, (steps, actions) actions (the dataset's ``actions_key``: ``actions``
    as applied, or the state machine's ``clean_actions``) of every episode in ``path``, and the task
    that recorded them."""
    from simlab.utils.datasets import HDF5DatasetFileHandler
    from simlab.utils.errors import ConfigError

    handler = HDF5DatasetFileHandler()
    handler.open(path)
    try:
        obs, actions = [], []
        for name in handler.get_episode_names():
            episode = handler.load_episode(name, "cpu").data
            recorded = episode.get("obs", {})
            missing = [t for t in terms if t not in recorded]
            if missing:
                raise ConfigError(
                    f"{path} {name} has no observation term {missing}; it has {sorted(recorded)}: choose --obs_terms"
                    " among those."
                )
            if actions_key not in episode:
                keys = sorted(k for k, v in episode.items() if isinstance(v, torch.Tensor))
                raise ConfigError(
                    f"{path} {name} has no '{actions_key}'; it has {keys}: choose --actions_key among those."
                )
            obs.append(torch.cat([recorded[t].reshape(len(recorded[t]), -1).float() for t in terms], dim=-1))
            actions.append(episode[actions_key].float())
        if not obs:
            raise ConfigError(f"{path} holds no episodes.")
        return torch.cat(obs), torch.cat(actions), handler.get_env_name()
    finally:
        handler.close()


def dataset_task(path: str) -> str | None:
    """The task whose episodes ``path`` holds (the recorder stores its name)."""
    from simlab.utils.datasets import HDF5DatasetFileHandler

    handler = HDF5DatasetFileHandler()
    handler.open(path)
    try:
        return handler.get_env_name()
    finally:
        handler.close()


def recipe_for(task: str | None) -> BCAgentCfg:
    """The BC recipe ``task`` registers (``bc_cfg_entry_point``), else :class:`BCAgentCfg`'s defaults."""
    import gymnasium as gym

    import simlab.tasks  # noqa: F401 - registers the tasks
    from simlab.tasks.utils.parse_cfg import load_cfg_from_registry

    spec = gym.registry.get(task) if task else None
    if spec is not None and "bc_cfg_entry_point" in spec.kwargs:
        return load_cfg_from_registry(task, "bc_cfg_entry_point")
    return BCAgentCfg()


def train(
    obs: torch.Tensor,
    actions: torch.Tensor,
    terms: list[str],
    hidden: list[int],
    epochs: int,
    batch_size: int = 256,
    lr: float = 1e-3,
    seed: int = 0,
    relative: int = 0,
    device: str = "cpu",
) -> tuple[BCPolicy, list[float]]:
    """Fit a :class:`BCPolicy` by mean squared error of the normalized actions on ``device``; returns it
    (on the CPU) and the mean loss of each epoch."""
    generator = torch.Generator().manual_seed(seed)
    torch.manual_seed(seed)
    obs, actions = obs.to(device), actions.to(device)
    policy = BCPolicy(terms, obs.shape[1], actions.shape[1], hidden, relative).to(device)
    actions = torch.cat([actions[:, :relative] - obs[:, :relative], actions[:, relative:]], dim=-1)
    policy.obs_mean[:] = obs.mean(0)
    policy.obs_std[:] = obs.std(0).clamp(min=1e-2)  # a term that barely moves is not blown up
    # each action dimension weighs alike: centimetres of the hand's position as much as the gripper's sign
    policy.action_mean[:], policy.action_std[:] = actions.mean(0), actions.std(0).clamp(min=1e-2)
    targets = (actions - policy.action_mean) / policy.action_std
    optimizer = torch.optim.Adam(policy.parameters(), lr=lr)
    schedule = torch.optim.lr_scheduler.CosineAnnealingLR(optimizer, epochs)
    losses = []
    for _ in range(epochs):
        order, total = torch.randperm(len(obs), generator=generator).to(device), torch.zeros((), device=device)
        for batch in order.split(batch_size):
            loss = (policy.normalized(obs[batch]) - targets[batch]).square().mean()
            optimizer.zero_grad()
            loss.backward()
            optimizer.step()
            total += loss.detach() * len(batch)  # summed on the device: no host read per batch
        schedule.step()
        losses.append(float(total) / len(obs))
    return policy.cpu().eval(), losses


def save(policy: BCPolicy, path: str, task: str | None, epochs: int | None = None) -> None:
    save_bc_policy(policy, path, task, epochs)


def load(path: str) -> tuple[BCPolicy, str | None]:
    """The policy in ``path`` and its task; weights only (a file from elsewhere runs no code)."""
    return load_bc_policy(path)


def play(task: str, policy: BCPolicy, num_envs: int, seed: int, seconds: float) -> tuple[float, bool, dict]:
    """Judge ``policy`` on ``task`` by its registered criterion (a seeded rollout as ``simlab play``'s,
    at least as long as the criterion asks); returns (score, passed, counts)."""
    import gymnasium as gym

    import simlab.tasks  # noqa: F401 - registers the tasks
    from simlab.cli.play import rollout
    from simlab.tasks.utils.criteria import criterion_for
    from simlab.tasks.utils.parse_cfg import parse_env_cfg

    criterion = criterion_for(task)
    cfg = parse_env_cfg(task, device="cpu", num_envs=num_envs)
    cfg.seed = seed
    env = gym.make(task, cfg=cfg)
    try:
        steps = max(1, round(criterion.play_seconds(seconds) / env.unwrapped.step_dt))
        hook, counts = criterion.make_hook()
        with torch.inference_mode():
            result = rollout(
                env, lambda obs: policy.act(obs["policy"]), steps, hook, stop_on_interrupt=False, seed=seed
            )
        score, passed = criterion.judge(result, counts)
    finally:
        env.close()
    return score, passed, counts


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description="Behaviour cloning from recorded demonstrations.")
    commands = parser.add_subparsers(dest="command", required=True)
    fit = commands.add_parser("train", help="Fit an MLP policy to a dataset's demonstrations.")
    fit.add_argument("--dataset_file", nargs="+", required=True, help="HDF5 datasets of simlab's recorder.")
    fit.add_argument("--out", required=True, help="Where the policy goes (a torch.save file).")
    # unset: the recipe the demonstrations' task registers (bc_cfg_entry_point), else BCAgentCfg's
    fit.add_argument("--obs_terms", nargs="+", default=None, help="Policy observation terms to read.")
    fit.add_argument(
        "--actions_key",
        default="actions",
        help="The labels: 'actions' (as applied) or 'clean_actions' (the state machine's, before its --noise).",
    )
    fit.add_argument("--hidden", type=int, nargs="+", default=None, help="Hidden layer widths.")
    fit.add_argument(
        "--relative",
        type=int,
        default=None,
        help="Leading actions predicted as offsets from the leading obs columns (3: the IK-Abs hand from eef_pos).",
    )
    for name, kind in (("epochs", int), ("batch_size", int), ("lr", float), ("seed", int)):
        fit.add_argument(f"--{name}", type=kind, default=None)
    fit.add_argument("--device", default="cpu", help="Where to train: cpu or cuda:N.")
    fit.add_argument("--threads", type=int, default=1, help="CPU threads torch trains with.")
    judge = commands.add_parser("play", help="Judge a policy by its task's registered criterion.")
    judge.add_argument("--checkpoint", required=True, help="A policy `train` wrote.")
    judge.add_argument("--task", default=None, help="Gymnasium id (default: the task the demonstrations are of).")
    judge.add_argument("--num_envs", type=int, default=32)
    judge.add_argument("--seed", type=int, default=42, help="Seed of the play (make_pretrained's default).")
    judge.add_argument("--seconds", type=float, default=5.0, help="Play at least this long (or the criterion's).")
    args = parser.parse_args(argv)

    if args.command == "train":
        recipe = recipe_for(dataset_task(args.dataset_file[0]))
        for name in ("obs_terms", "hidden", "relative", "epochs", "batch_size", "lr", "seed"):
            if getattr(args, name) is None:
                setattr(args, name, getattr(recipe, name))
        obs, actions, tasks = zip(*(load_demos(path, args.obs_terms, args.actions_key) for path in args.dataset_file))
        if len(set(tasks)) > 1:
            parser.error(f"the datasets hold demonstrations of several tasks: {sorted(map(str, set(tasks)))}")
        obs, actions, task = torch.cat(obs), torch.cat(actions), tasks[0]
        start = time.perf_counter()
        torch.set_num_threads(args.threads)
        policy, losses = train(
            obs,
            actions,
            args.obs_terms,
            args.hidden,
            args.epochs,
            args.batch_size,
            args.lr,
            args.seed,
            args.relative,
            args.device,
        )
        save(policy, args.out, task, args.epochs)
        print(
            f"[simlab] BC on {len(obs)} steps of {task}: loss {losses[0]:.4g} -> {losses[-1]:.4g} in {args.epochs}"
            f" epochs ({time.perf_counter() - start:.1f} s); saved {args.out}"
        )
        return
    policy, trained_on = load(args.checkpoint)
    task = args.task or trained_on
    if task is None:
        parser.error(f"{args.checkpoint} names no task: give --task")
    score, passed, counts = play(task, policy, args.num_envs, args.seed, args.seconds)
    print(f"[simlab] {task}: score {score:.3f} ({counts}); the criterion {'passes' if passed else 'fails'}")


if __name__ == "__main__":
    from simlab.utils.errors import is_intended_error

    try:
        main()
    except Exception as error:  # bad input (a missing dataset, a term it lacks) in one line, as the CLI does
        if not is_intended_error(error):
            raise
        print(f"bc.py: error: {error}", file=sys.stderr)
        sys.exit(2)
