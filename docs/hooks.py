"""MkDocs hooks (mkdocs.yml ``hooks:``): the task gallery page, written from the Gymnasium registry.

The gallery's pictures are build outputs of ``scripts/tools/render_gallery.py`` (one PNG per task),
kept out of git. They are read from ``$SIMLAB_GALLERY_DIR`` (default ``build/gallery`` beside
mkdocs.yml) and copied into the site; a task without a picture is listed with a note, unless
``SIMLAB_GALLERY_REQUIRED=1`` (``scripts/build_docs.sh``), which makes a missing picture an error.
"""

from __future__ import annotations

import os
import sys

import gymnasium as gym
from mkdocs.exceptions import PluginError
from mkdocs.structure.files import File, Files

GALLERY_PAGE = "gallery.md"
MARKER = "<!-- tasks -->"


def _gallery_dir(config) -> str:
    root = os.path.dirname(config.config_file_path)
    return os.path.join(root, os.environ.get("SIMLAB_GALLERY_DIR", os.path.join("build", "gallery")))


def _picture_name(task: str) -> str:
    # the same rule as scripts/tools/render_gallery.py's picture_name
    return task.replace("/", "__") + ".png"


def on_files(files: Files, config) -> Files:
    """Copy the rendered pictures into the site under ``gallery/``."""
    folder = _gallery_dir(config)
    if os.path.isdir(folder):
        for name in sorted(os.listdir(folder)):
            if name.endswith(".png") and not name.endswith(".tmp.png"):
                files.append(File.generated(config, f"gallery/{name}", abs_src_path=os.path.join(folder, name)))
    return files


def _description(cfg_class: type) -> str:
    """The first paragraph of the env config's docstring, else of the task package that holds it
    (a config class without a docstring has the signature dataclasses write in its place)."""
    doc = cfg_class.__doc__ or ""
    if not doc or doc.startswith(cfg_class.__name__ + "("):
        package = cfg_class.__module__.rpartition(".")[0]
        doc = sys.modules[package].__doc__ or ""
    return " ".join(doc.strip().split("\n\n")[0].split())


def _summary(task: str) -> tuple[str, str, str]:
    """The task's workflow, its one-line description and its agent configs."""
    from simlab.tasks.utils import load_cfg_from_registry

    spec = gym.spec(task)
    doc = _description(type(load_cfg_from_registry(task, "env_cfg_entry_point")))
    entry = spec.entry_point if isinstance(spec.entry_point, str) else ""
    workflow = "direct" if ".direct." in entry else "manager-based"
    agents = [k.removesuffix("_cfg_entry_point") for k in spec.kwargs if k.endswith("_cfg_entry_point")]
    return workflow, doc.replace("|", "\\|"), ", ".join(a for a in agents if a != "env")


def on_page_markdown(markdown: str, page, config, files: Files) -> str:
    """Replace the gallery page's marker by a table of every registered task with its picture."""
    if page.file.src_uri != GALLERY_PAGE:
        return markdown
    if MARKER not in markdown:
        raise PluginError(f"docs/{GALLERY_PAGE} lost its marker {MARKER!r}, where the task table goes")
    from simlab.pretrained import list_pretrained
    from simlab.tasks.utils import registered_task_ids

    shipped: dict[str, list[str]] = {}
    for task, library in list_pretrained():
        shipped.setdefault(task, []).append(library)
    required = os.environ.get("SIMLAB_GALLERY_REQUIRED") == "1"
    rows = ["| picture | task | workflow | agent configs | shipped policy |", "| --- | --- | --- | --- | --- |"]
    missing = []
    for task in registered_task_ids():
        picture = f"gallery/{_picture_name(task)}"
        if files.get_file_from_path(picture) is not None:
            image = f"![{task}]({picture})"
        else:
            missing.append(task)
            image = "(not rendered)"
        workflow, doc, agents = _summary(task)
        policy = ", ".join(shipped.get(task, [])) or "-"
        rows.append(f"| {image} | `{task}`<br>{doc} | {workflow} | {agents} | {policy} |")
    if missing and required:
        raise PluginError(f"no gallery picture for {missing} in {_gallery_dir(config)}: run render_gallery.py")
    return markdown.replace(MARKER, "\n".join(rows))
