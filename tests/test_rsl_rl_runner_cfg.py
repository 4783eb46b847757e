"""rsl_rl's runner configs share ``RslRlBaseRunnerCfg`` (as Isaac Lab's do): every registered rsl_rl agent
hands its runner exactly the keys that runner reads, and the shared fields are declared once."""

from __future__ import annotations

import dataclasses

import gymnasium as gym
import pytest

import simlab.tasks  # noqa: F401  (registers the tasks)
from simlab.rl.rsl_rl import RslRlBaseRunnerCfg, RslRlDistillationRunnerCfg, RslRlOnPolicyRunnerCfg
from simlab.tasks.utils.parse_cfg import _load_entry_point

RUNNER_KEYS = {
    "seed", "device", "num_steps_per_env", "max_iterations", "obs_groups", "clip_actions", "check_for_nan",
    "save_interval", "experiment_name", "run_name", "logger", "wandb_project", "neptune_project", "resume",
    "load_run", "load_checkpoint",
}  # fmt: skip
KEYS = {
    RslRlOnPolicyRunnerCfg: RUNNER_KEYS | {"actor", "critic", "algorithm"},
    RslRlDistillationRunnerCfg: RUNNER_KEYS | {"student", "teacher", "algorithm"},
}


def _rsl_rl_entry_points() -> list[tuple[str, str, object]]:
    """(task, key, entry point) of every rsl_rl agent a task registers, its presets' included."""
    found = []
    for name, spec in sorted(gym.registry.items()):
        kwargs = spec.kwargs or {}
        tables = [kwargs, *(kwargs.get("presets") or {}).values()]
        for table in tables:
            found += [(name, k, ep) for k, ep in table.items() if k.startswith("rsl_rl") and k.endswith("entry_point")]
    return found


def test_every_registered_rsl_rl_agent_gives_its_runner_exactly_the_keys_it_reads():
    entry_points = _rsl_rl_entry_points()
    assert len(entry_points) > 50 and any("distillation" in k for _, k, _ in entry_points)
    for task, key, entry_point in entry_points:
        cfg = _load_entry_point(entry_point, key)
        runner = next(c for c in KEYS if isinstance(cfg, c))
        assert isinstance(cfg, RslRlBaseRunnerCfg)
        assert set(cfg.to_rsl_rl_dict(["policy", "critic"])) == KEYS[runner], (task, key)


def test_the_shared_runner_fields_are_declared_once():
    base = {f.name for f in dataclasses.fields(RslRlBaseRunnerCfg)}
    assert base == RUNNER_KEYS
    for runner in KEYS:
        assert not base & set(vars(runner).get("__annotations__", {})), runner.__name__
        assert [f.name for f in dataclasses.fields(runner)][: len(base)] == [
            f.name for f in dataclasses.fields(RslRlBaseRunnerCfg)
        ]


@pytest.mark.parametrize(
    ("obs_groups", "env_groups", "expected"),
    [
        ({}, ["policy"], {"actor": ["policy"], "critic": ["policy"]}),
        ({}, ["policy", "critic"], {"actor": ["policy"], "critic": ["critic"]}),
        ({"actor": ["a"]}, ["policy", "critic"], {"actor": ["a"]}),  # set: taken as it is
    ],
)
def test_ppo_obs_groups_are_filled_only_when_empty(obs_groups, env_groups, expected):
    assert RslRlOnPolicyRunnerCfg()._fill_obs_groups(dict(obs_groups), env_groups) == expected


@pytest.mark.parametrize(
    ("obs_groups", "env_groups", "expected"),
    [
        ({}, ["policy"], {"student": ["policy"], "teacher": ["teacher"]}),
        ({}, ["student", "teacher"], {"student": ["student"], "teacher": ["teacher"]}),
        ({"teacher": ["policy"]}, ["policy"], {"student": ["policy"], "teacher": ["policy"]}),
    ],
)
def test_distillation_obs_groups_fill_each_set_left_out(obs_groups, env_groups, expected):
    assert RslRlDistillationRunnerCfg()._fill_obs_groups(dict(obs_groups), env_groups) == expected
