"""Name matching with regexes (joints, bodies, terms) and callable <-> string."""

from __future__ import annotations

import os.path

import pytest

from simlab.utils.string import (
    callable_to_string,
    closest_matches,
    resolve_matching_names,
    resolve_matching_names_values,
    string_to_callable,
)

JOINTS = ["LF_HAA", "LF_HFE", "RF_HAA", "RF_HFE", "LH_HAA", "LH_HFE"]


def test_single_regex_key():
    assert resolve_matching_names(".*_HAA", JOINTS) == ([0, 2, 4], ["LF_HAA", "RF_HAA", "LH_HAA"])


def test_full_match_not_prefix_match():
    # "LF_HA" is a prefix of "LF_HAA" but not a full match
    with pytest.raises(ValueError, match="LF_HA"):
        resolve_matching_names("LF_HA", JOINTS)
    assert resolve_matching_names("LF_HAA", JOINTS) == ([0], ["LF_HAA"])


def test_list_of_keys_order_of_strings_by_default():
    keys = ["RF_.*", "LF_HFE"]
    assert resolve_matching_names(keys, JOINTS) == ([1, 2, 3], ["LF_HFE", "RF_HAA", "RF_HFE"])


def test_preserve_order_follows_keys():
    keys = ["RF_.*", "LF_HFE"]
    assert resolve_matching_names(keys, JOINTS, preserve_order=True) == (
        [2, 3, 1],
        ["RF_HAA", "RF_HFE", "LF_HFE"],
    )


def test_unmatched_key_lists_keys_and_available_strings():
    with pytest.raises(ValueError) as err:
        resolve_matching_names(["LF_.*", "knee", "hip"], JOINTS)
    msg = str(err.value)
    assert "['knee', 'hip']" in msg
    for j in JOINTS:
        assert j in msg


def test_string_matched_by_two_keys_errors():
    with pytest.raises(ValueError, match="LF_HAA"):
        resolve_matching_names(["LF_.*", ".*_HAA"], JOINTS)


def test_invalid_regex_and_non_string_keys():
    with pytest.raises(ValueError, match="not a valid regular expression"):
        resolve_matching_names("LF_(", JOINTS)
    with pytest.raises(TypeError, match="strings"):
        resolve_matching_names([1], JOINTS)


def test_resolve_values():
    data = {".*_HAA": 0.1, "LF_HFE": 0.5, "(RF|LH)_HFE": -0.5}
    ids, names, values = resolve_matching_names_values(data, JOINTS)
    assert ids == [0, 1, 2, 3, 4, 5]
    assert values == [0.1, 0.5, 0.1, -0.5, 0.1, -0.5]
    ids, names, values = resolve_matching_names_values(data, JOINTS, preserve_order=True)
    assert names == ["LF_HAA", "RF_HAA", "LH_HAA", "LF_HFE", "RF_HFE", "LH_HFE"]
    assert values == [0.1, 0.1, 0.1, 0.5, -0.5, -0.5]


def test_resolve_values_errors():
    with pytest.raises(ValueError, match="foot"):
        resolve_matching_names_values({"foot": 1.0}, JOINTS)
    with pytest.raises(TypeError, match="dict"):
        resolve_matching_names_values([".*"], JOINTS)


def test_callable_round_trip():
    s = callable_to_string(os.path.join)
    assert s == f"{os.path.join.__module__}:join"
    assert string_to_callable(s) is os.path.join
    assert string_to_callable("collections:OrderedDict") is __import__("collections").OrderedDict
    assert string_to_callable("os.path.join") is os.path.join  # dotted form too


def test_callable_nested_qualname():
    class Outer:
        @staticmethod
        def inner():
            return 1

    assert callable_to_string(Outer.inner).endswith("test_callable_nested_qualname.<locals>.Outer.inner")


def test_string_to_callable_errors():
    with pytest.raises(ValueError, match="module 'not_a_module_xyz'"):
        string_to_callable("not_a_module_xyz:f")
    with pytest.raises(ValueError, match="has no attribute 'jion'.*'join'"):
        string_to_callable("os.path:jion")
    with pytest.raises(ValueError, match="module:qualname"):
        string_to_callable("nocolon")
    with pytest.raises(ValueError, match="not callable"):
        string_to_callable("os:sep")


def test_lambdas_round_trip_as_source_and_unsafe_ones_are_refused():
    square = lambda x: x**2  # noqa: E731
    assert callable_to_string(square) == "lambda x: x**2"
    assert string_to_callable(callable_to_string(square))(3) == 9
    assert string_to_callable("lambda x, y=2: max(x, y) if x else len([y])")(0) == 1
    for unsafe in ('lambda x: __import__("os")', "lambda x: x.__class__", "lambda: open('f')", "lambda x: (y := x)"):
        with pytest.raises(ValueError, match="Unsafe lambda expression"):
            string_to_callable(unsafe)
    with pytest.raises(ValueError, match="callable"):
        callable_to_string(3)


def _make_exported():
    def exported():
        return "ok"

    return exported


exported = _make_exported()


def test_function_made_in_a_function_uses_its_exported_name():
    assert callable_to_string(exported) == f"{__name__}:exported"
    assert string_to_callable(callable_to_string(exported)) is exported


def test_closest_matches():
    assert closest_matches("num_env", ["num_envs", "env_spacing", "seed"])[0] == "num_envs"
    assert closest_matches("zzz", ["num_envs", "seed"]) == []
