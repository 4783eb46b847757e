"""``SceneEntityCfg``: names a scene entity and the joints/bodies of it that a term uses.

Terms take it as a parameter (``SceneEntityCfg("robot", joint_names=["slider_to_cart"])``); the
manager resolves the names to ids once the simulation has started, so the term indexes
``asset.data.joint_pos[:, asset_cfg.joint_ids]`` without looking names up every step.
"""

from __future__ import annotations

from dataclasses import MISSING

from simlab.utils import configclass


@configclass
class SceneEntityCfg:
    name: str = MISSING
    """Name of the entity in the scene config (``scene["robot"]``)."""
    joint_names: str | list[str] | None = None
    joint_ids: list[int] | slice = slice(None)
    """Filled from ``joint_names``; ``slice(None)`` means all joints (a view, no copy)."""
    fixed_tendon_names: str | list[str] | None = None
    fixed_tendon_ids: list[int] | slice = slice(None)
    """Always empty once resolved: simlab's models have no fixed tendons."""
    body_names: str | list[str] | None = None
    body_ids: list[int] | slice = slice(None)
    """Filled from ``body_names`` (articulation bodies, or a contact sensor's bodies)."""
    preserve_order: bool = False
    """Order ids as the names are listed rather than in the model's order."""

    def resolve(self, scene) -> None:
        """Check the entity exists and fill ``joint_ids`` / ``body_ids`` from the names (or the reverse)."""
        if self.name not in scene:
            raise ValueError(f"the scene has no entity '{self.name}'; entities: {scene.keys()}")
        entity = scene[self.name]
        self.joint_ids, self.joint_names = self._resolve(entity, "joint", self.joint_names, self.joint_ids)
        self.body_ids, self.body_names = self._resolve(entity, "body", self.body_names, self.body_ids)
        if self.fixed_tendon_names is not None:
            # simlab's models have no fixed tendons (coupled joints are equality constraints): nothing to select
            self.fixed_tendon_ids = []

    def _resolve(self, entity, kind: str, names, ids):
        find = getattr(entity, "find_joints" if kind == "joint" else "find_bodies", None)
        all_names = getattr(entity, f"{kind}_names", None)
        if names is None and (ids is None or ids == slice(None)):
            return slice(None), names
        if find is None or all_names is None:
            raise ValueError(f"entity '{self.name}' ({type(entity).__name__}) has no {kind}s to select")
        if names is not None:
            found_ids, found_names = find(names, preserve_order=self.preserve_order)
            if not self.preserve_order and found_ids == list(range(len(all_names))):
                return slice(None), found_names  # all of them: index with a slice (a view)
            if ids is not None and ids != slice(None) and list(ids) != found_ids:
                raise ValueError(f"entity '{self.name}': {kind}_ids {ids} disagree with {kind}_names {names}")
            return found_ids, found_names
        if isinstance(ids, slice):
            return ids, all_names[ids]
        ids = [int(i) for i in ids]
        bad = [i for i in ids if not 0 <= i < len(all_names)]
        if bad:
            raise ValueError(f"entity '{self.name}': {kind}_ids {bad} out of range; it has {len(all_names)} {kind}s")
        return ids, [all_names[i] for i in ids]
