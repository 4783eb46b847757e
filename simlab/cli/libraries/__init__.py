"""One adapter per RL library: configure, train (with resume and Ctrl+C saves) and load a policy.

Each module has ``experiment_name(agent_cfg, task)``, ``configure(agent_cfg, args, env_cfg)``,
``train(env, agent_cfg, run_dir, args, resume_path)`` and ``load_policy(env, agent_cfg, checkpoint, trust)``.
Optional hooks, looked up by name: ``init_weights`` (``--init_weights``), ``needs_teacher(agent_cfg)`` and
``is_teacher_checkpoint(path, trust)`` (distillation; a library without them never distils).
Checkpoints load as weights only unless ``trust`` (``args.trust_checkpoint`` when training):
:mod:`simlab.utils.trust`.
"""

from __future__ import annotations

import importlib
from types import ModuleType

__all__ = ["get_library"]


def get_library(name: str) -> ModuleType:
    """The adapter module of library ``name`` (its library is imported only when used)."""
    return importlib.import_module(f"{__name__}.{name}")
