"""Isaac Lab's base config of its asset converters (``isaaclab.sim.converters``)."""

from __future__ import annotations

from dataclasses import MISSING

from simlab.utils import configclass


@configclass
class AssetConverterBaseCfg:
    """Where a converter writes its output. Isaac Lab writes USD; simlab's converters write MJCF."""

    asset_path: str = MISSING
    """The file to convert."""
    usd_dir: str | None = None
    """Directory of the converted file; None: a new directory under the system's temporary one."""
    usd_file_name: str | None = None
    """Name of the converted file; None: the asset's. Its extension becomes ``.xml`` (an MJCF file)."""
    force_usd_conversion: bool = False
    """Convert again even when the converted file exists."""
    make_instanceable: bool = True
    """Accepted and ignored: every MuJoCo world holds its own copy of the model anyway."""
