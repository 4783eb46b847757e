#!/usr/bin/env bash
# Build the documentation site into site/ (or the folder given): render the task gallery's
# pictures into build/gallery, then `mkdocs build` (strict: a broken link fails it).
#   bash scripts/build_docs.sh            # site/
#   bash scripts/build_docs.sh /tmp/site  # elsewhere
# Needs the docs extra: pip install -c constraints.txt -e ".[docs]" (setup.sh dev installs it).
set -euo pipefail
cd "$(dirname "$0")/.."
export MUJOCO_GL="${MUJOCO_GL:-osmesa}" NO_MKDOCS_2_WARNING=1
export SIMLAB_GALLERY_DIR="${SIMLAB_GALLERY_DIR:-build/gallery}" SIMLAB_GALLERY_REQUIRED=1
.venv/bin/python scripts/tools/render_gallery.py --out "$SIMLAB_GALLERY_DIR"
.venv/bin/python -m mkdocs build --strict --site-dir "${1:-site}"
