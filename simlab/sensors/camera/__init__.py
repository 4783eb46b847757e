"""Camera sensors: batched RGB, depth and segmentation images (Isaac Lab's ``Camera`` / ``TiledCamera``)."""

from .camera import DATA_TYPES, Camera, TiledCamera
from .camera_cfg import CameraCfg, TiledCameraCfg
from .camera_data import CameraData
from .utils import create_pointcloud_from_depth, save_images_to_file, tile_images
