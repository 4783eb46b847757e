"""Isaac Lab 3.0's command-line words in simlab's terms.

Isaac Lab 3.0 runs ``isaaclab train --rl_library rsl_rl --task Isaac-Cartpole --viz newton_gl
physics=newton_mjwarp presets=rgb``. ``simlab train`` / ``play`` take the same words:

* ``--rl_library`` is ``--library`` (an argparse alias, in :mod:`simlab.cli.main`);
* ``--viz`` / ``--visualizer`` name a live viewer: simlab's ``native``, ``web``, ``none``, or 3.0's
  backend names where simlab has the same thing (:func:`simlab.viewer.choice.viewer_for_visualizer`);
  the others are refused;
* ``physics=``, ``renderer=`` and ``presets=`` are Hydra selectors (words without a ``env.`` /
  ``agent.`` prefix): the physics engine, the offscreen renderer, and the task's registered variants
  (``kwargs["presets"]``, :func:`simlab.tasks.utils.parse_cfg.registry_kwargs`). ``presets=`` may
  also name a physics or renderer backend, as 3.0's benchmarks write ``presets=newton_mjwarp,rgb``.

Each translation prints one ``[simlab]`` line saying what it became; a name simlab cannot honour is a
ConfigError saying what to use instead.
"""

from __future__ import annotations

import argparse
import contextlib
import os
from collections.abc import Iterator

from simlab.sim.backend_names import FOREIGN_PHYSICS, PHYSICS, engine_for
from simlab.utils.errors import ConfigError

__all__ = ["SELECTORS", "apply_selectors", "apply_visualizer", "renderer_choice", "split_selectors"]

SELECTORS = ("physics", "renderer", "presets")

RENDERERS = {  # 3.0's name -> SIMLAB_RENDERER
    "opengl": "opengl",
    "mujoco": "opengl",
    "warp": "warp",
    "newton_renderer": "warp",  # Newton's Warp ray tracer -> MuJoCo Warp's
    "newton_warp": "warp",
}
RENDERER_ADVICE = (
    "simlab renders with MuJoCo: use renderer=opengl (MuJoCo's OpenGL renderer) or renderer=newton_renderer "
    "(MuJoCo Warp's ray tracer, for simulations on the GPU)"
)
# renderer names of Isaac Lab 3.0 that simlab knows and refuses (anything else in presets= is a task preset)
FOREIGN_RENDERERS = ("isaacsim_rtx_renderer", "ovrtx_renderer", "rtx")


def split_selectors(overrides: list[str]) -> tuple[dict[str, str], list[str]]:
    """``(selectors, overrides)``: the ``physics=`` / ``renderer=`` / ``presets=`` words apart from the rest."""
    selectors: dict[str, str] = {}
    rest = []
    for word in overrides:
        key, _, value = word.partition("=")
        if key in SELECTORS:
            if key in selectors:
                raise ConfigError(f"{key}= is given twice ({key}={selectors[key]} and {word}): give it once.")
            selectors[key] = value
        else:
            rest.append(word)
    return selectors, rest


def _names(key: str, value: str) -> list[str]:
    names = [name.strip().lower() for name in value.split(",")]
    if not all(names):
        raise ConfigError(
            f"{key}={value}: give names separated by commas, e.g. {key}=rgb or presets=newton_mjwarp,rgb."
        )
    return names


def _physics(name: str, args: argparse.Namespace) -> None:
    engine = engine_for(name)
    if engine == "mujoco":
        if (args.device or "cpu").startswith("cuda"):
            raise ConfigError(
                f"physics={name} runs on the CPU, but --device {args.device} asks for the GPU: "
                "use physics=newton_mjwarp on the GPU."
            )
        args.device = "cpu"
    args.engine = engine
    args.physics = name  # also chooses the task's physics presets (simlab.tasks.utils.presets)
    print(f"[simlab] physics={name} -> sim.engine={engine}" + (" on the CPU" if engine == "mujoco" else ""))


def _renderer(name: str, args: argparse.Namespace) -> None:
    if name not in RENDERERS:
        raise ConfigError(f"renderer={name}: {RENDERER_ADVICE}.")
    args.renderer = RENDERERS[name]
    print(f"[simlab] renderer={name} -> SIMLAB_RENDERER={args.renderer}")


def apply_selectors(args: argparse.Namespace, selectors: dict[str, str]) -> None:
    """Set ``args.engine``, ``args.renderer`` and ``args.presets`` (a list of the task's preset names)
    from the selectors; refuse names simlab cannot honour."""
    args.engine = getattr(args, "engine", None)
    args.renderer = getattr(args, "renderer", None)
    args.physics = None
    args.presets = []
    for key, apply in (("physics", _physics), ("renderer", _renderer)):
        if key in selectors:
            names = _names(key, selectors[key])
            if len(names) != 1:
                raise ConfigError(f"{key}={selectors[key]}: name one backend.")
            apply(names[0], args)
    for name in _names("presets", selectors["presets"]) if "presets" in selectors else []:
        if name in PHYSICS or name in FOREIGN_PHYSICS:
            _physics(name, args)
        elif name in FOREIGN_RENDERERS or (name.endswith("_renderer") and name != "newton_renderer"):
            raise ConfigError(f"presets={name}: {RENDERER_ADVICE}.")
        elif name == "newton_renderer":
            _renderer(name, args)
        else:
            args.presets.append(name)
    if args.presets:
        print(f"[simlab] presets: {', '.join(args.presets)} (the task's registered variants)")


def apply_visualizer(args: argparse.Namespace) -> None:
    """Turn ``--viz`` / ``--visualizer`` (comma-separated, 3.0's form) into simlab's ``--viewer``."""
    from simlab.viewer.choice import viewer_for_visualizer

    value = getattr(args, "visualizer", None)
    if value is None:
        return
    kind = viewer_for_visualizer(value)
    if args.viewer not in ("auto", kind):
        raise ConfigError(f"--viz {value} and --viewer {args.viewer} ask for different viewers: give one of them.")
    args.viewer = kind
    if value.lower() != kind:
        print(f"[simlab] --viz {value} -> --viewer {kind}")


@contextlib.contextmanager
def renderer_choice(renderer: str | None) -> Iterator[None]:
    """Within the block, the offscreen renderer is ``renderer`` (``SIMLAB_RENDERER``; None: unchanged)."""
    if renderer is None:
        yield
        return
    previous = os.environ.get("SIMLAB_RENDERER")
    os.environ["SIMLAB_RENDERER"] = renderer
    try:
        yield
    finally:
        if previous is None:
            os.environ.pop("SIMLAB_RENDERER", None)
        else:
            os.environ["SIMLAB_RENDERER"] = previous
