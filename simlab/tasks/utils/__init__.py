"""Task utilities: configs from the registry, checkpoint lookup, Hydra-style overrides."""

from .hydra import apply_overrides, hydra_task_config
from .parse_cfg import get_checkpoint_path, load_cfg_from_registry, parse_env_cfg, registered_task_ids, simlab_task_id
from .presets import PresetCfg, preset

__all__ = [
    "PresetCfg",
    "apply_overrides",
    "get_checkpoint_path",
    "hydra_task_config",
    "load_cfg_from_registry",
    "parse_env_cfg",
    "preset",
    "registered_task_ids",
]
