"""String helpers: regex name matching (joints, bodies, terms) and callable <-> "module:qualname"."""

from __future__ import annotations

import ast
import builtins
import contextlib
import difflib
import functools
import importlib
import inspect
import re
import sys
import textwrap
from collections.abc import Callable, Iterable, Iterator, Sequence
from typing import Any

__all__ = [
    "ResolvableString",
    "callable_modules",
    "callable_to_string",
    "clear_resolve_matching_names_cache",
    "closest_matches",
    "find_root_prim_path_from_regex",
    "find_unique_string_name",
    "is_lambda_expression",
    "resolve_matching_names",
    "resolve_matching_names_values",
    "simlab_task_id",
    "string_to_callable",
    "string_to_slice",
    "to_camel_case",
    "to_snake_case",
]


def closest_matches(word: str, candidates: Sequence[str], n: int = 3, cutoff: float = 0.5) -> list[str]:
    """The candidates most similar to ``word`` (difflib ratio), best first; empty if none is close."""
    return difflib.get_close_matches(str(word), [str(c) for c in candidates], n=n, cutoff=cutoff)


def _did_you_mean(word: str, candidates: Sequence[str]) -> str:
    close = closest_matches(word, candidates, n=1)
    return f" Did you mean '{close[0]}'?" if close else ""


def _as_key_list(keys: str | Sequence[str]) -> list[str]:
    if isinstance(keys, str):
        return [keys]
    keys = list(keys)
    for k in keys:
        if not isinstance(k, str):
            raise TypeError(f"Keys must be strings (regular expressions), got {k!r} of type {type(k).__name__}.")
    return keys


def _compile(key: str) -> re.Pattern:
    try:
        return re.compile(key)
    except re.error as e:
        raise ValueError(f"Key '{key}' is not a valid regular expression: {e}.") from e


def resolve_matching_names(
    keys: str | Sequence[str], list_of_strings: Sequence[str], preserve_order: bool = False
) -> tuple[list[int], list[str]]:
    """Match regex ``keys`` (full match) against ``list_of_strings``.

    Returns ``(indices, names)`` of the matched strings. By default they come in the order of
    ``list_of_strings``; with ``preserve_order=True`` in the order of the keys (strings matched
    by one key keep their order among themselves). Results are cached (see
    :func:`clear_resolve_matching_names_cache`).

    Raises:
        ValueError: a key matches nothing, or one string is matched by more than one key.
    """
    order, _ = _resolve_matching_names_impl(tuple(_as_key_list(keys)), tuple(list_of_strings), preserve_order, True)
    strings = list(list_of_strings)
    return list(order), [strings[i] for i in order]


@functools.lru_cache(maxsize=1024)
def _resolve_matching_names_impl(
    keys: tuple[str, ...], strings: tuple[str, ...], preserve_order: bool, strict: bool
) -> tuple[tuple[int, ...], tuple[int, ...]]:
    """``(string indices, index of the key that matched each)``; ``strict``: every key must match."""
    patterns = [_compile(k) for k in keys]
    matched_key_of: dict[int, int] = {}  # string index -> key index
    key_hits = [0] * len(keys)
    for s_idx, name in enumerate(strings):
        for k_idx, pattern in enumerate(patterns):
            if pattern.fullmatch(name):
                if s_idx in matched_key_of:
                    other = keys[matched_key_of[s_idx]]
                    raise ValueError(
                        f"Multiple matches for '{name}': '{other}' and '{keys[k_idx]}'."
                        " Each string may be matched by only one key."
                    )
                matched_key_of[s_idx] = k_idx
                key_hits[k_idx] += 1

    unmatched = [k for k, hits in zip(keys, key_hits) if hits == 0]
    if strict and unmatched:
        hints = "".join(_did_you_mean(k, strings) for k in unmatched)
        raise ValueError(
            f"Not all regular expressions are matched! Unmatched keys: {unmatched}."
            f" Available strings: {list(strings)}.{hints}"
        )

    if preserve_order:
        order = sorted(matched_key_of, key=lambda s_idx: (matched_key_of[s_idx], s_idx))
    else:
        order = sorted(matched_key_of)
    return tuple(order), tuple(matched_key_of[i] for i in order)


def clear_resolve_matching_names_cache() -> None:
    """Forget the cached results of :func:`resolve_matching_names` (e.g. to free memory)."""
    _resolve_matching_names_impl.cache_clear()


def resolve_matching_names_values(
    data: dict[str, Any], list_of_strings: Sequence[str], preserve_order: bool = False, strict: bool = True
) -> tuple[list[int], list[str], list[Any]]:
    """Like :func:`resolve_matching_names`, with ``data`` mapping regex keys to values.

    Returns ``(indices, names, values)`` where ``values[i]`` is the value of the key that
    matched ``names[i]``. E.g. ``{".*_hip": 0.1, "knee": 0.5}`` gives one value per matched joint.
    With ``strict=False`` keys that match nothing are ignored (a string matched twice still raises).
    """
    if not isinstance(data, dict):
        raise TypeError(
            f"Input argument `data` should be a dictionary of {{regex: value}}, got {type(data).__name__}: {data!r}."
        )
    keys = tuple(_as_key_list(list(data.keys())))
    order, key_of = _resolve_matching_names_impl(keys, tuple(list_of_strings), preserve_order, strict)
    strings = list(list_of_strings)
    return list(order), [strings[i] for i in order], [data[keys[k]] for k in key_of]


def is_lambda_expression(obj: Any) -> bool:
    return inspect.isfunction(obj) and obj.__name__ == "<lambda>"


def _lambda_source(value: Callable) -> str:
    """The source text of a lambda, e.g. ``"lambda x: x**2"`` (found with ``ast`` in its source lines)."""
    try:
        lines, _ = inspect.getsourcelines(value)
    except (OSError, TypeError) as e:
        raise ValueError(f"Cannot turn the lambda {value!r} into a string: its source is not available ({e}).") from e
    source = textwrap.dedent("".join(lines))
    for text in (source, f"(\n{source}\n)"):  # a lambda inside a call spanning lines parses once wrapped
        try:
            tree = ast.parse(text)
        except SyntaxError:
            continue
        args = value.__code__.co_varnames[: value.__code__.co_argcount]
        found = [
            ast.get_source_segment(text, node)
            for node in ast.walk(tree)
            if isinstance(node, ast.Lambda) and tuple(a.arg for a in node.args.args) == args
        ]
        if len(found) == 1:
            return found[0]
        if len(found) > 1:
            raise ValueError(
                f"Cannot turn the lambda {value!r} into a string: its source line holds {len(found)} lambdas with"
                " the same arguments. Put it on its own line or use a named function."
            )
    raise ValueError(f"Cannot turn the lambda {value!r} into a string: no lambda found in its source.")


def callable_to_string(value: Callable) -> str:
    """``"module:qualname"`` for a function or class, e.g. ``"simlab.envs.mdp:joint_pos"``.

    A lambda gives its source text (``"lambda x: x**2"``), which :func:`string_to_callable` reads
    back; a bound method gives ``"module:method_name"`` as in Isaac Lab.
    """
    if not callable(value):
        raise ValueError(f"Expected a callable (function or class), got {type(value).__name__}: {value!r}.")
    if is_lambda_expression(value):
        return _lambda_source(value)
    module = getattr(value, "__module__", None)
    qualname = getattr(value, "__qualname__", None) or getattr(value, "__name__", None)
    if inspect.ismethod(value) and not isinstance(value.__self__, type):
        qualname = value.__name__  # bound to an instance: no importable path to that instance
    if module is None or qualname is None:
        # e.g. functools.partial or a callable instance: describe its type instead
        module, qualname = type(value).__module__, type(value).__qualname__
    if "<locals>" in qualname:
        # made inside a function: use the module-level name if the module exports this very object
        name = getattr(value, "__name__", "")
        if getattr(sys.modules.get(module), name, None) is value:
            return f"{module}:{name}"
    return f"{module}:{qualname}"


# Builtins a lambda string may call; everything else it names must be one of its own arguments.
_SAFE_LAMBDA_BUILTINS = {
    name: getattr(builtins, name)
    for name in ("abs", "all", "any", "bool", "dict", "float", "int", "len", "list", "max", "min", "range", "round")
    + ("set", "sorted", "str", "sum", "tuple", "zip", "True", "False", "None")
}


def _safe_lambda(source: str) -> Callable:
    """Evaluate a lambda expression string that can only compute on its arguments.

    Rejected: names other than its arguments and a few pure builtins, any ``_``-prefixed name or
    attribute (no walking into Python internals), nested lambdas, comprehensions and ``:=``.
    """
    try:
        tree = ast.parse(source.strip(), mode="eval")
    except SyntaxError as e:
        raise ValueError(f"Cannot parse the lambda expression '{source}': {e.msg}.") from e
    if not isinstance(tree.body, ast.Lambda):
        raise ValueError(f"Expected a lambda expression, got '{source}'.")
    lam = tree.body
    params = {a.arg for a in (*lam.args.posonlyargs, *lam.args.args, *lam.args.kwonlyargs)}
    params |= {a.arg for a in (lam.args.vararg, lam.args.kwarg) if a is not None}
    forbidden = (ast.Lambda, ast.NamedExpr, ast.ListComp, ast.SetComp, ast.DictComp, ast.GeneratorExp, ast.Await)
    for node in ast.walk(lam.body):
        unsafe = isinstance(node, forbidden)
        unsafe |= isinstance(node, ast.Attribute) and node.attr.startswith("_")
        unsafe |= isinstance(node, ast.Name) and (
            node.id.startswith("_") or node.id not in params | set(_SAFE_LAMBDA_BUILTINS)
        )
        if unsafe:
            raise ValueError(
                f"Unsafe lambda expression '{source}': it may only use its arguments, operators, public attributes"
                f" and the builtins {sorted(_SAFE_LAMBDA_BUILTINS)} (offending part: '{ast.unparse(node)}')."
            )
    return eval(compile(tree, "<lambda string>", "eval"), {"__builtins__": dict(_SAFE_LAMBDA_BUILTINS)})


# the packages whose functions a "module:name" text may name; None: any (Python code naming its own)
_ALLOWED_MODULES: list[tuple[str, ...] | None] = [None]


@contextlib.contextmanager
def callable_modules(packages: Iterable[str]) -> Iterator[None]:
    """Within the block, :func:`string_to_callable` resolves ``"module:name"`` only inside ``packages``
    (and their sub-modules), and refuses any other module before importing it.

    The ``simlab`` command runs each command inside this block with simlab, the task's own package and
    the modules given with ``--allow_module``: a value in an override or a run's ``params/env.yaml``
    (``env.rewards.alive.func=pydoc:pipepager``) cannot reach ``os``, ``subprocess`` or ``pydoc``.
    """
    _ALLOWED_MODULES.append(tuple(sorted(set(packages))))
    try:
        yield
    finally:
        _ALLOWED_MODULES.pop()


def allowed_callable_packages() -> tuple[str, ...] | None:
    """The packages the innermost :func:`callable_modules` block allows; None outside any block."""
    return _ALLOWED_MODULES[-1]


def _check_module(name: str, module_name: str) -> None:
    allowed = _ALLOWED_MODULES[-1]
    if allowed is None or any(module_name == p or module_name.startswith(p + ".") for p in allowed):
        return
    root = module_name.split(".")[0]
    raise ValueError(
        f"'{name}' names the module '{module_name}', which is outside {', '.join(allowed)}: a 'module:name' value"
        f" may name only those; pass --allow_module {root} to allow it."
    )


def string_to_callable(name: str) -> Callable:
    """Resolve ``"module:qualname"`` (or ``"module.attr"``) to the object it names.

    A lambda expression string (``"lambda x: x + 1"``) is evaluated in a sandbox that only lets it
    compute on its arguments (see :func:`_safe_lambda`). Inside :func:`callable_modules` only the
    modules it allows resolve.
    """
    if not isinstance(name, str):
        raise TypeError(f"Expected a string 'module:qualname', got {type(name).__name__}: {name!r}.")
    if name.lstrip().startswith("lambda"):
        return _safe_lambda(name)
    if ":" in name:
        module_name, _, attr_path = name.partition(":")
    else:
        module_name, _, attr_path = name.rpartition(".")
    if not module_name or not attr_path:
        raise ValueError(
            f"Could not resolve '{name}': expected 'module:qualname' (e.g. 'simlab.envs.mdp:joint_pos')"
            " or 'module.attr'."
        )
    _check_module(name, module_name)
    try:
        obj: Any = importlib.import_module(module_name)
    except ImportError as e:
        raise ValueError(f"Could not resolve '{name}': module '{module_name}' could not be imported ({e}).") from e
    for part in attr_path.split("."):
        if not hasattr(obj, part):
            public = [a for a in dir(obj) if not a.startswith("_")]
            raise ValueError(
                f"Could not resolve '{name}': '{getattr(obj, '__name__', obj)}' has no attribute '{part}'."
                + _did_you_mean(part, public)
            )
        obj = getattr(obj, part)
    if not callable(obj):
        raise ValueError(f"'{name}' resolves to {obj!r}, which is not callable.")
    return obj


class ResolvableString(str):
    """A ``"module:qualname"`` string that behaves as the callable it names, imported on first use.

    ``__module__``, ``__qualname__`` and ``__name__`` are read from the string without importing;
    calling it (or reading a public attribute) resolves it with :func:`string_to_callable` once.
    Dunder probes such as ``hasattr(ref, "__dataclass_fields__")`` never trigger the import.
    """

    def _parts(self) -> tuple[str, str]:
        text = str.__str__(self)
        module, sep, qualname = text.partition(":")
        if not sep:
            module, _, qualname = text.rpartition(".")
        return module, qualname

    def __getattribute__(self, name: str) -> Any:
        if name == "__module__":
            return ResolvableString._parts(self)[0]
        if name == "__qualname__":
            return ResolvableString._parts(self)[1]
        if name == "__name__":
            return ResolvableString._parts(self)[1].rsplit(".", 1)[-1]
        return super().__getattribute__(name)

    def __getattr__(self, name: str) -> Any:
        if name.startswith("__") and name.endswith("__"):
            raise AttributeError(name)  # introspection must not import anything
        return getattr(self.resolve(), name)

    def resolve(self) -> Callable:
        """The callable this string names (imported once, then cached)."""
        cached = self.__dict__.get("_resolved")
        if cached is None:
            cached = string_to_callable(str.__str__(self))
            self.__dict__["_resolved"] = cached
        return cached

    def __call__(self, *args: Any, **kwargs: Any) -> Any:
        return self.resolve()(*args, **kwargs)


# -- case conversion and slices --------------------------------------------------------------------


def to_camel_case(snake_str: str, to: str = "cC") -> str:
    """``"snake_case_string"`` to ``"snakeCaseString"`` (``to="cC"``) or ``"SnakeCaseString"`` (``to="CC"``)."""
    if to not in ("cC", "CC"):
        raise ValueError(f"to_camel_case: 'to' must be 'cC' (lower camel) or 'CC' (upper camel), got {to!r}.")
    words = snake_str.lower().split("_")
    first = words[0].capitalize() if to == "CC" else words[0]
    return first + "".join(w.capitalize() for w in words[1:])


def to_snake_case(camel_str: str) -> str:
    """``"CamelCaseString"`` or ``"camelCaseString"`` to ``"camel_case_string"``."""
    # split before an upper-case letter that follows a lower-case letter or digit, or that starts a
    # word after an acronym ("HTTPServer" -> "http_server")
    words = re.sub(r"(?<=[a-z0-9])(?=[A-Z])|(?<=[A-Z])(?=[A-Z][a-z])", "_", camel_str)
    return words.lower()


_SLICE_STR = re.compile(r"^slice\((.*)\)$")


def string_to_slice(s: str) -> slice:
    """``"slice(1, 10, 2)"`` (as written by ``str(slice(...))``) back to the slice."""
    match = _SLICE_STR.match(s.strip()) if isinstance(s, str) else None
    if match is None:
        raise ValueError(f"Expected a string like 'slice(start, stop, step)', got {s!r}.")
    parts = [p.strip() for p in match.group(1).split(",")]
    if not 1 <= len(parts) <= 3:
        raise ValueError(f"A slice takes one to three arguments, got {len(parts)} in {s!r}.")
    try:
        values = [None if p == "None" else int(p) for p in parts]
    except ValueError as e:
        raise ValueError(f"Slice arguments must be integers or None, got {s!r}.") from e
    return slice(*values)


# -- names -----------------------------------------------------------------------------------------


def find_unique_string_name(initial_name: str, is_unique_fn: Callable[[str], bool]) -> str:
    """``initial_name``, or ``initial_name_N`` with the smallest N >= 1 for which ``is_unique_fn`` holds."""
    if is_unique_fn(initial_name):
        return initial_name
    n = 1
    while not is_unique_fn(f"{initial_name}_{n}"):
        n += 1
    return f"{initial_name}_{n}"


def find_root_prim_path_from_regex(prim_path_regex: str) -> tuple[str, int]:
    """The path above the first regex element of a prim path, and that element's depth.

    ``"/World/envs/env_.*/Robot"`` gives ``("/World/envs", 3)``; a path without a regex gives itself
    and the depth of its last element.
    """
    parts = str(prim_path_regex).split("/")
    for depth, part in enumerate(parts):
        if any(c in part for c in "[]*|^"):
            return "/".join(parts[:depth]), depth
    return prim_path_regex, len(parts) - 1


def simlab_task_id(task: str) -> str:
    """Isaac Lab's ``Isaac-<Name>`` id as simlab's ``simlab/<Name>`` (the porting map), and an id without a
    version (Isaac Lab 3.0's ``Isaac-Cartpole``, ``simlab/Cartpole``) as its highest registered version
    (``simlab/Cartpole-v0``); other ids unchanged. Versions are looked up in Gymnasium's registry, so the
    tasks are registered first (``import simlab.tasks``)."""
    mapped = "simlab/" + task.removeprefix("Isaac-") if task.startswith("Isaac-") else task
    if mapped.startswith("simlab/") and not re.search(r"-v\d+$", mapped):
        from gymnasium.envs.registration import find_highest_version

        version = find_highest_version("simlab", mapped.removeprefix("simlab/"))
        if version is not None:
            return f"{mapped}-v{version}"
    return mapped
