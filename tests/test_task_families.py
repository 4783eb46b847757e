"""docs/task_families.md: Isaac Lab's task families with simlab's status, from docs/task_families.yaml,
the Gymnasium registry and the shipped policies (docs/hooks.py)."""

from __future__ import annotations

import importlib.util
import os

import pytest
import yaml

from simlab.pretrained import list_pretrained
from simlab.tasks.utils import registered_task_ids

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DATA = os.path.join(REPO, "docs", "task_families.yaml")


def _hooks():
    spec = importlib.util.spec_from_file_location("docs_hooks", os.path.join(REPO, "docs", "hooks.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_every_registered_task_is_in_one_family_and_every_listed_id_is_registered():
    rows = _hooks().family_rows(DATA)
    registered = registered_task_ids()
    placed = [task for row in rows for task in row["registered"]]
    assert sorted(placed) == sorted(set(placed)), "a task is in two families"
    assert set(placed) == set(registered), f"not in docs/task_families.yaml: {sorted(set(registered) - set(placed))}"
    for row in rows:
        assert all(task in registered for task in row["registered"])
        # a family simlab lacks says why; one it has is not explained away
        assert row["registered"] or row.get("why_not"), f"{row['family']}: no simlab task and no why_not"


def test_the_status_columns_come_from_the_shipped_policies():
    rows = _hooks().family_rows(DATA)
    shipped = {(task, library) for row in rows for task, libs in row["shipped"].items() for library in libs}
    assert shipped == {(t, lib) for t, lib in list_pretrained() if "-Play" not in t}
    cartpole = next(row for row in rows if row["family"] == "Cartpole")
    assert {"rsl_rl", "skrl"} <= set(cartpole["shipped"]["simlab/Cartpole-v0"])
    assert "simlab/Cartpole-v0" in cartpole["learns"] and "simlab/Cartpole-v0" not in cartpole["untrained"]
    table = _hooks().families_table(DATA)
    assert table.count("\n| ") == len(rows) + 2  # the header, its separator and one line per family


def test_a_listed_simlab_id_that_is_not_registered_is_an_error(tmp_path):
    with open(DATA) as f:
        families = yaml.safe_load(f)
    families[0]["simlab"] = ["simlab/Nothing-Like-This-v0"]
    path = tmp_path / "families.yaml"
    path.write_text(yaml.safe_dump(families))
    with pytest.raises(ValueError, match="Nothing-Like-This-v0"):
        _hooks().family_rows(str(path))
