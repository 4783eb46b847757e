"""The viewer camera: where ``env.render()`` looks from, and the offscreen renderer it uses."""

from __future__ import annotations

import numpy as np


def make_renderer(model, viewer_cfg):
    from simlab.sim.renderer import OffscreenRenderer

    width, height = viewer_cfg.resolution
    return OffscreenRenderer(model, width, height)


def render_frame(renderer, env, viewer_cfg) -> np.ndarray:
    """Render env ``viewer_cfg.env_index`` from the viewer camera (same frames as the manager-based env)."""
    eye, lookat = camera_pose(env, viewer_cfg)
    return renderer.render(env.sim.physics, viewer_cfg.env_index, eye, lookat)


def camera_pose(env, viewer) -> tuple[np.ndarray, np.ndarray]:
    """The viewer's eye and look-at point in the frame of the rendered MuJoCo world.

    Each env is its own MuJoCo world centred on zero, so world-frame points lose the env origin;
    ``origin_type`` "env" / "asset_root" / "asset_body" places them relative to that env, asset or body.
    """
    index = viewer.env_index
    if not 0 <= index < env.num_envs:
        raise ValueError(f"cfg.viewer.env_index is {index}, but there are {env.num_envs} envs")
    eye, lookat = np.asarray(viewer.eye, dtype=np.float64), np.asarray(viewer.lookat, dtype=np.float64)
    origin = env.scene.env_origins[index].cpu().numpy().astype(np.float64)
    if viewer.origin_type == "world":
        offset = -origin
    elif viewer.origin_type == "env":
        offset = np.zeros(3)
    elif viewer.origin_type in ("asset_root", "asset_body"):
        if viewer.asset_name is None:
            raise ValueError(f"cfg.viewer.origin_type='{viewer.origin_type}' needs cfg.viewer.asset_name")
        asset = env.scene[viewer.asset_name]
        if viewer.origin_type == "asset_root":
            pos = asset.data.root_pos_w[index]
        else:
            body_ids, _ = asset.find_bodies(viewer.body_name)
            pos = asset.data.body_pos_w[index, body_ids[0]]
        offset = pos.cpu().numpy().astype(np.float64) - origin
    else:
        raise ValueError(
            f"Unknown cfg.viewer.origin_type '{viewer.origin_type}'; allowed: world, env, asset_root, asset_body"
        )
    return eye + offset, lookat + offset
