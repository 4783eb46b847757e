"""The documentation site (mkdocs.yml): it builds strictly, with the API reference, the porting table
taken from the README and the task gallery; a broken link or anchor fails the build.

The default test renders the gallery's picture of one task (seconds); the slow one renders every
task and requires a picture of each, as scripts/build_docs.sh does."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys

import pytest
import yaml
from conftest import rendering_available

pytest.importorskip("mkdocs")
pytest.importorskip("mkdocstrings")
pytest.importorskip("material")

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
needs_rendering = pytest.mark.skipif(not rendering_available(), reason="no offscreen OpenGL (libosmesa6 or EGL)")


def _mkdocs(config: str, site: str, **env: str) -> subprocess.CompletedProcess:
    command = [sys.executable, "-m", "mkdocs", "build", "--strict", "-f", config, "--site-dir", site]
    env = dict(os.environ, NO_MKDOCS_2_WARNING="1", **env)
    return subprocess.run(command, cwd=REPO, env=env, capture_output=True, text=True, timeout=600)


def _build_site(tmp_path, tasks: list[str] | None):
    """Render the gallery of ``tasks`` (all when None) and build the site; a missing picture of a
    task that was to be rendered fails the build. Returns the site's folder."""
    gallery = tmp_path / "gallery"
    render = [sys.executable, os.path.join(REPO, "scripts", "tools", "render_gallery.py"), "--out", str(gallery)]
    done = subprocess.run(render + (["--tasks", *tasks] if tasks else []), cwd=REPO, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr[-3000:]
    site = tmp_path / "site"
    env = {"SIMLAB_GALLERY_DIR": str(gallery)} | ({} if tasks else {"SIMLAB_GALLERY_REQUIRED": "1"})
    built = _mkdocs(os.path.join(REPO, "mkdocs.yml"), str(site), **env)
    assert built.returncode == 0, built.stdout[-3000:] + built.stderr[-3000:]
    return site


@needs_rendering
def test_the_site_builds_strictly_with_api_reference_porting_table_and_gallery(tmp_path):
    from simlab.tasks.utils import registered_task_ids

    site = _build_site(tmp_path, ["simlab/Cartpole-v0"])
    page = (site / "gallery" / "index.html").read_text()
    for task in registered_task_ids():  # every task is listed; the one rendered has its picture
        assert f"<code>{task}</code>" in page, task
    assert '<img alt="simlab/Cartpole-v0" src="simlab__Cartpole-v0.png"' in page
    assert page.count("<img alt=") == 1 and (site / "gallery" / "simlab__Cartpole-v0.png").stat().st_size > 1000
    # the API reference comes from the docstrings; the porting page takes the README's table
    assert (
        'id="simlab.envs.manager_based_rl_env.ManagerBasedRLEnv"' in (site / "api" / "envs" / "index.html").read_text()
    )
    porting = (site / "porting" / "index.html").read_text()
    assert "<code>isaaclab_rl</code>" in porting and "<code>simlab.rl</code>" in porting
    # the task families page: its table written by docs/hooks.py from docs/task_families.yaml
    families = (site / "task_families" / "index.html").read_text()
    assert "<code>Isaac-Lift-Teddy-Bear-Franka-IK-Abs-v0</code>" in families and "<!-- families -->" not in families
    assert "<code>Cartpole-v0</code>: rsl_rl" in families


@needs_rendering
def test_the_gallery_renders_discrete_actions_and_a_play_variant_that_needs_a_trained_file(tmp_path):
    """A Discrete action is one column (the showcase's zero actions); the vision hand's Play variant
    needs a CNN only training writes, so from a fresh folder it is pictured as its training variant."""
    gallery = tmp_path / "gallery"
    render = [sys.executable, os.path.join(REPO, "scripts", "tools", "render_gallery.py"), "--out", str(gallery)]
    tasks = ["Showcase-Box-Discrete-Direct", "Shadow-Vision-Direct-Play"]
    done = subprocess.run(render + ["--tasks", *tasks], cwd=tmp_path, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr[-3000:]
    assert "picturing simlab/Repose-Cube-Shadow-Vision-Direct-v0 instead" in done.stdout
    for task in ("simlab/Cartpole-Showcase-Box-Discrete-Direct-v0", "simlab/Repose-Cube-Shadow-Vision-Direct-Play-v0"):
        assert (gallery / (task.replace("/", "__") + ".png")).stat().st_size > 1000, task


@pytest.mark.slow
@needs_rendering
def test_every_task_renders_into_the_gallery(tmp_path):
    from simlab.tasks.utils import registered_task_ids

    site = _build_site(tmp_path, None)
    page = (site / "gallery" / "index.html").read_text()
    assert page.count("<img alt=") == len(registered_task_ids())


def test_a_broken_link_or_anchor_or_a_page_left_out_of_the_nav_fails_the_build(tmp_path):
    """The site's own config and validation on a copy of docs/ with two bad links and a page missing
    from the nav (without the API reference and the gallery hook, which take seconds and check
    nothing here)."""
    docs = tmp_path / "docs"
    shutil.copytree(os.path.join(REPO, "docs"), docs, ignore=shutil.ignore_patterns("bench", "__pycache__"))
    for page in (docs / "api").glob("*.md"):
        page.write_text(f"# {page.stem}\n")
    with open(docs / "usage.md", "a") as f:
        f.write("\nSee [a page](no_such_page.md) and [a section](env_step.md#no-such-section).\n")
    (docs / "orphan.md").write_text("# A page the nav does not list\n")
    with open(os.path.join(REPO, "mkdocs.yml")) as f:
        config = yaml.safe_load(f)
    config["docs_dir"] = str(docs)
    config["hooks"] = []
    config["plugins"] = [p for p in config["plugins"] if p == "search"]
    (tmp_path / "mkdocs.yml").write_text(yaml.safe_dump(config))

    built = _mkdocs(str(tmp_path / "mkdocs.yml"), str(tmp_path / "site"))
    log = built.stdout + built.stderr
    assert built.returncode != 0, log[-3000:]
    assert "no_such_page.md" in log and "no-such-section" in log and "orphan.md" in log, log[-3000:]


def test_every_subpackage_has_an_api_page_in_the_nav():
    """The API reference is one page per subpackage of simlab (``simlab.pretrained`` holds data)."""
    packages = {
        name for name in os.listdir(os.path.join(REPO, "simlab")) if name != "pretrained" and not name.startswith("_")
    }
    packages = {name for name in packages if os.path.isfile(os.path.join(REPO, "simlab", name, "__init__.py"))}
    with open(os.path.join(REPO, "mkdocs.yml")) as f:
        (api,) = [section["API reference"] for section in yaml.safe_load(f)["nav"] if "API reference" in section]
    pages = {os.path.basename(next(iter(entry.values()))) for entry in api}
    assert {f"{name}.md" for name in packages} <= pages, sorted({f"{name}.md" for name in packages} - pages)
