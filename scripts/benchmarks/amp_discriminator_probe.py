"""How easily can an AMP discriminator tell the simulated humanoid from its reference clip, and by which features?

    python scripts/benchmarks/amp_discriminator_probe.py                       # the walk clip, every feature group
    python scripts/benchmarks/amp_discriminator_probe.py --motion_file my.npz  # a user's clip

The "policy" is the sim playing the clip as well as open-loop PD tracking can: envs start in
reference states (RSI) and each step sets the joint targets to the clip's next pose; its AMP
observations of the first ``--steps`` steps (before open-loop tracking falls) are the fake samples,
``collect_reference_motions`` (what skrl's motion dataset holds) the real ones. A discriminator
with skrl AMP's losses (BCE, gradient penalty on the reference samples, logit regularisation,
weight decay) is trained on them, once on all features and once on each feature group alone, and
judged on held-out samples: ``D(sim)`` near 0 (style reward ``-log(1 - D)`` near 0) means the
features give the simulated body away even when it moves like the clip; a group that does so alone
is a feature of the clip that the sim cannot reproduce (e.g. a torso with zero angular velocity).
"""

from __future__ import annotations

import argparse

import gymnasium as gym
import torch
from torch import nn

import simlab.tasks  # noqa: F401 - registers the tasks
from simlab.tasks.utils import load_cfg_from_registry

FEATURE_GROUPS = ("joint_pos", "joint_vel", "height", "orientation", "lin_vel", "ang_vel", "key_bodies")


def feature_columns(num_joints: int, num_keys: int) -> dict[str, list[int]]:
    """Columns of each feature group in one AMP frame (``compute_obs``'s order)."""
    sizes = (num_joints, num_joints, 1, 6, 3, 3, 3 * num_keys)
    columns, start = {}, 0
    for name, size in zip(FEATURE_GROUPS, sizes):
        columns[name] = list(range(start, start + size))
        start += size
    return columns


def collect(env, steps: int, episodes: int) -> tuple[torch.Tensor, torch.Tensor]:
    """AMP observations of the sim tracking the clip with PD targets (fake) and of the clip (real)."""
    base = env.unwrapped
    motion, n = base._motion_loader, base.num_envs
    grid = torch.linspace(0, motion.duration, 2000, device=base.device)
    grid_poses = motion.sample(2000, times=grid)[0][:, base.motion_dof_indexes]
    env.reset()
    fake = []
    for _ in range(episodes):
        base._reset_mask(torch.ones(n, dtype=torch.bool, device=base.device))
        # the clip time of each env's reference state: the clip pose nearest to its joints
        times = grid[torch.cdist(base.robot.data.joint_pos, grid_poses).argmin(dim=1)]
        for step in range(steps):
            times = times + base.step_dt
            targets = motion.sample(n, times=torch.remainder(times, motion.duration))[0][:, base.motion_dof_indexes]
            _, _, terminated, _, extras = env.step((targets - base.action_offset) / base.action_scale)
            if step > 0:  # the first transition's history still holds the reference frames
                fake.append(extras["amp_obs"][~terminated].clone())
    fake = torch.cat(fake)
    return fake, base.collect_reference_motions(2 * len(fake))


def discriminator_score(fake: torch.Tensor, real: torch.Tensor, iterations: int, seed: int) -> tuple[float, float]:
    """Train a discriminator on half of each set; its mean output on the other halves (real, fake)."""
    torch.manual_seed(seed)
    fake_train, fake_test = fake.chunk(2)
    real_train, real_test = real.chunk(2)
    both = torch.cat([fake_train, real_train])
    mean, std = both.mean(0), both.std(0) + 1e-2  # a standard scaler, as skrl's preprocessor

    def scale(x: torch.Tensor) -> torch.Tensor:
        return (x - mean) / std

    net = nn.Sequential(nn.Linear(fake.shape[1], 256), nn.ReLU(), nn.Linear(256, 128), nn.ReLU(), nn.Linear(128, 1))
    optimizer = torch.optim.Adam(net.parameters(), lr=1e-4)
    bce = nn.BCEWithLogitsLoss()
    for _ in range(iterations):
        fake_logits = net(scale(fake_train[torch.randint(0, len(fake_train), (512,))]))
        real_batch = scale(real_train[torch.randint(0, len(real_train), (512,))]).requires_grad_(True)
        real_logits = net(real_batch)
        loss = 0.5 * (bce(fake_logits, torch.zeros_like(fake_logits)) + bce(real_logits, torch.ones_like(real_logits)))
        (gradient,) = torch.autograd.grad(real_logits, real_batch, torch.ones_like(real_logits), create_graph=True)
        loss = loss + 5.0 * gradient.square().sum(-1).mean()  # skrl's discriminator_gradient_penalty_scale
        loss = loss + 0.05 * net[-1].weight.square().sum()  # discriminator_logit_regularization_scale
        loss = loss + 1e-4 * sum(m.weight.square().sum() for m in net if isinstance(m, nn.Linear))
        optimizer.zero_grad()
        loss.backward()
        optimizer.step()
    with torch.no_grad():
        return float(torch.sigmoid(net(scale(real_test))).mean()), float(torch.sigmoid(net(scale(fake_test))).mean())


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--motion", choices=("walk", "run", "dance"), default="walk")
    parser.add_argument("--motion_file", default=None, help="A clip in Isaac Lab's format (default: the task's).")
    parser.add_argument("--num_envs", type=int, default=128)
    parser.add_argument("--steps", type=int, default=8, help="Tracking steps per episode (0.27 s at 30 Hz).")
    parser.add_argument("--episodes", type=int, default=3)
    parser.add_argument("--iterations", type=int, default=600, help="Discriminator training steps.")
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()

    task = f"simlab/Humanoid-AMP-{args.motion.capitalize()}-Direct-v0"
    cfg = load_cfg_from_registry(task, "env_cfg_entry_point")
    cfg.scene.num_envs, cfg.sim.device, cfg.seed = args.num_envs, "cpu", args.seed
    if args.motion_file:
        cfg.motion_file = args.motion_file
    env = gym.make(task, cfg=cfg)
    try:
        fake, real = collect(env, args.steps, args.episodes)
        base = env.unwrapped
        columns = feature_columns(base.robot.num_joints, len(base.cfg.key_bodies))
    finally:
        env.close()
    frame, frames = base.cfg.amp_observation_space, base.cfg.num_amp_observations
    print(f"{cfg.motion_file}: {len(fake)} sim samples, {len(real)} reference samples")
    print(f"{'features':<12} {'D(reference)':>12} {'D(sim)':>8} {'style reward of sim':>20}")
    for group in ("all", *FEATURE_GROUPS):
        cols = (
            list(range(frame * frames))
            if group == "all"
            else [c + frame * f for f in range(frames) for c in columns[group]]
        )
        d_real, d_fake = discriminator_score(fake[:, cols], real[:, cols], args.iterations, args.seed)
        style = -torch.log(torch.clamp(torch.tensor(1.0 - d_fake), min=1e-4))
        print(f"{group:<12} {d_real:>12.3f} {d_fake:>8.3f} {float(style):>20.3f}")


if __name__ == "__main__":
    main()
