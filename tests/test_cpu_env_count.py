"""A task's CPU env count (``scene.num_envs_cpu``): used on the CPU unless the user sets a count."""

from __future__ import annotations

import pytest

from simlab.cli.main import build_parser
from simlab.cli.session import load_configs


def _num_envs(*argv: str, overrides: tuple[str, ...] = ()) -> int:
    args = build_parser().parse_args(["train", "--task", "simlab/Cartpole-v0", *argv])
    env_cfg, _ = load_configs(args, list(overrides))
    return env_cfg.scene.num_envs


@pytest.mark.parametrize(
    ("argv", "overrides", "expected"),
    [
        (("--device", "cpu"), (), 1024),  # the cartpole's CPU default
        (("--device", "cpu", "--num_envs", "4096"), (), 4096),  # a flag wins
        (("--device", "cpu"), ("env.scene.num_envs=512",), 512),  # so does an override
        (("--device", "cpu"), ("env.scene.num_envs_cpu=256",), 256),
        (("--device", "cpu"), ("env.scene.num_envs_cpu=null",), 4096),  # None: num_envs on every device
    ],
)
def test_the_cpu_env_count_applies_only_when_no_count_is_given(argv, overrides, expected):
    assert _num_envs(*argv, overrides=overrides) == expected


def test_other_devices_keep_num_envs(monkeypatch):
    import simlab.utils.device as device_rules

    monkeypatch.setattr(device_rules, "resolve_device", lambda device: device)  # no GPU needed to read the config
    assert _num_envs("--device", "cuda:0") == 4096
