"""Helpers of the environments: Gymnasium spaces from config specs, multi-agent conversion."""

from .spaces import (
    deserialize_space,
    replace_env_cfg_spaces_with_strings,
    replace_strings_with_env_cfg_spaces,
    sample_space,
    serialize_space,
    spec_to_gym_space,
)

__all__ = [
    "deserialize_space",
    "replace_env_cfg_spaces_with_strings",
    "replace_strings_with_env_cfg_spaces",
    "sample_space",
    "serialize_space",
    "spec_to_gym_space",
]
