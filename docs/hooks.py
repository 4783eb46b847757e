"""MkDocs hooks (mkdocs.yml ``hooks:``): the task gallery page, written from the Gymnasium registry, and
the task families page: Isaac Lab's families (``docs/task_families.yaml``) with simlab's status for each,
from the registry and the shipped policies (``simlab/pretrained/``).

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
FAMILIES_PAGE = "task_families.md"
FAMILIES_MARKER = "<!-- families -->"
FAMILIES_DATA = os.path.join("docs", "task_families.yaml")  # the hand-written part, beside mkdocs.yml


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
    """Replace the gallery page's marker by a table of every registered task with its picture, and the
    task families page's by :func:`families_table`."""
    if page.file.src_uri == FAMILIES_PAGE:
        if FAMILIES_MARKER not in markdown:
            raise PluginError(f"docs/{FAMILIES_PAGE} lost its marker {FAMILIES_MARKER!r}, where the table goes")
        try:
            table = families_table(os.path.join(os.path.dirname(config.config_file_path), FAMILIES_DATA))
        except ValueError as e:
            raise PluginError(str(e)) from e
        return markdown.replace(FAMILIES_MARKER, table)
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


def _learned(task: str, library: str) -> str:
    """Where the shipped policy met its task's criterion (its record), e.g. ``cuda:0``."""
    from simlab.pretrained import pretrained_record

    record = pretrained_record(task, library)
    if record is None:  # the first cartpoles' record.txt: judged on the CPU
        return "cpu"
    return record.get("evaluation", {}).get("device") or "cpu replay"


def family_rows(data_file: str) -> list[dict]:
    """The families of ``data_file`` with their status: ``registered`` (simlab's ids, -Play variants
    included), ``learns`` (tasks whose shipped policy met the criterion, and where), ``untrained`` and
    ``shipped`` (task -> libraries). Raises ValueError for a listed simlab id that is not registered."""
    import yaml

    from simlab.pretrained import list_pretrained
    from simlab.tasks.utils import registered_task_ids
    from simlab.utils.string import simlab_task_id

    with open(data_file) as f:
        families = yaml.safe_load(f)
    registered = registered_task_ids()
    shipped: dict[str, list[str]] = {}
    for task, library in list_pretrained():
        shipped.setdefault(task, []).append(library)
    rows = []
    for family in families:
        unknown = [t for t in family.get("simlab", []) if t not in registered]
        if unknown:
            raise ValueError(f"{data_file}: {family['family']} lists {unknown}, which simlab does not register")
        named = {simlab_task_id(t) for t in family["isaaclab"]} | set(family.get("simlab", []))
        ids = [t for t in registered if t in named or t.replace("-Play", "") in named]
        trained = [t for t in ids if "-Play" not in t]
        rows.append(
            {
                **family,
                "registered": ids,
                "learns": {t: [_learned(t, lib) for lib in shipped[t]] for t in trained if t in shipped},
                "untrained": [t for t in trained if t not in shipped],
                "shipped": {t: shipped[t] for t in trained if t in shipped},
            }
        )
    return rows


def families_table(data_file: str) -> str:
    """The task families page's table (markdown): one row per family of ``data_file``."""

    def names(tasks) -> str:
        return ", ".join(f"`{t.removeprefix('simlab/')}`" for t in tasks)

    lines = [
        "| group | family | Isaac Lab ids | simlab ids | learns | shipped policy | why not |",
        "| --- | --- | --- | --- | --- | --- | --- |",
    ]
    rows = family_rows(data_file)
    registered = sum(1 for row in rows if row["registered"])
    learning = sum(1 for row in rows if row["learns"])
    summary = (
        f"{registered} of the {len(rows)} families are registered; {learning} have at least one task whose"
        " shipped policy met its criterion.\n\n"
    )
    for row in rows:
        learns = [f"`{t.removeprefix('simlab/')}` ({', '.join(sorted(set(d)))})" for t, d in row["learns"].items()]
        if row["untrained"]:
            learns.append(f"not yet trained: {names(row['untrained'])}")
        policies = [f"`{t.removeprefix('simlab/')}`: {', '.join(libs)}" for t, libs in row["shipped"].items()]
        cells = [
            row["group"],
            row["family"],
            names(row["isaaclab"]) or "-",
            names(row["registered"]) or "not registered",
            "<br>".join(learns) or "-",
            "<br>".join(policies) or "-",
            "" if row["registered"] else row.get("why_not", ""),
        ]
        lines.append("| " + " | ".join(c.replace("|", "\\|") for c in cells) + " |")
    return summary + "\n".join(lines)
