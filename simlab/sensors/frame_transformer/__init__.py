"""Frame transformer: target frames relative to a source frame (Isaac Lab's ``sensors.frame_transformer``)."""

from .frame_transformer import FrameTransformer
from .frame_transformer_cfg import FrameTransformerCfg, OffsetCfg
from .frame_transformer_data import FrameTransformerData
