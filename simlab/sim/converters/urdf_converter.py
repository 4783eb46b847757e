"""Isaac Lab's ``UrdfConverter``: here MuJoCo compiles the URDF and the result is written as MJCF.

Isaac Lab converts a URDF into a USD file that scenes then spawn with ``UsdFileCfg(usd_path=...)``.
simlab writes an MJCF file instead, at ``converter.usd_path`` (the name is Isaac Lab's); a
``UsdFileCfg`` naming a local MJCF file spawns it, so the tutorial's two steps run unchanged.
"""

from __future__ import annotations

import os
import tempfile
from dataclasses import MISSING

import mujoco

from simlab.utils.assets import refuse_remote_path
from simlab.utils.errors import ConfigError

from ..spawners.from_files.from_files import fuse_static_bodies
from .urdf_converter_cfg import UrdfConverterCfg


class UrdfConverter:
    """Compile ``cfg.asset_path`` with MuJoCo's URDF reader and write it as MJCF (unless it exists)."""

    def __init__(self, cfg: UrdfConverterCfg):
        if cfg.fix_base is MISSING or cfg.asset_path is MISSING:
            raise ConfigError("UrdfConverterCfg needs asset_path and fix_base (True welds the root link to the world).")
        refuse_remote_path(cfg.asset_path)
        source = os.path.abspath(os.path.expanduser(cfg.asset_path))
        if not os.path.isfile(source):
            raise ConfigError(f"UrdfConverterCfg.asset_path: no such file '{cfg.asset_path}'.")
        self.cfg = cfg
        self._usd_dir = cfg.usd_dir or tempfile.mkdtemp(prefix="simlab_converted_")
        stem = os.path.splitext(cfg.usd_file_name or os.path.basename(source))[0]
        self._usd_file_name = f"{stem}.xml"
        if cfg.force_usd_conversion or not os.path.isfile(self.usd_path):
            os.makedirs(self._usd_dir, exist_ok=True)
            self._convert(source)

    @property
    def usd_dir(self) -> str:
        return self._usd_dir

    @property
    def usd_file_name(self) -> str:
        return self._usd_file_name

    @property
    def usd_path(self) -> str:
        """The converted file: MJCF, which ``UsdFileCfg(usd_path=...)`` and ``MjcfFileCfg`` spawn."""
        return os.path.join(self._usd_dir, self._usd_file_name)

    def _convert(self, source: str) -> None:
        spec = mujoco.MjSpec.from_file(source)
        if self.cfg.merge_fixed_joints:
            spec = fuse_static_bodies(spec, source)
        else:  # meshes and textures stay where the URDF names them, relative to its own directory
            base = os.path.dirname(source)
            spec.meshdir = os.path.join(base, spec.meshdir) if spec.meshdir else base
            spec.texturedir = os.path.join(base, spec.texturedir) if spec.texturedir else base
        spec.compiler.fusestatic = False  # MuJoCo's URDF default is True; merging was asked for above or not at all
        if not self.cfg.fix_base:
            _add_free_joint(spec)
        spec.compile()  # a URDF MuJoCo cannot compile fails here, naming the problem
        with open(self.usd_path, "w") as file:
            file.write(spec.to_xml())


def _add_free_joint(spec: mujoco.MjSpec) -> None:
    """A free joint on the single root body, unless it has a joint (handles into the spec stay in here:
    one that outlives its spec points to freed memory)."""
    roots = spec.worldbody.bodies
    if len(roots) == 1 and not roots[0].joints:
        roots[0].add_freejoint()
