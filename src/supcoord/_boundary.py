"""Argument checks at the public boundary: a wrong type is the user's mistake, said in one line.

:func:`checked` wraps a public function (``supcoord.<name>``) so that every argument is
checked against the function's own annotations before the call: a ``Problem`` where a
``Problem`` is expected, a path (``str`` or ``os.PathLike``) where a file is expected, an
integer (not a bool) where an ``int`` is, a number where a ``float`` is, one of the
values of a ``Literal``.  A mismatch raises :class:`~supcoord.errors.InputError` naming
the function, the parameter and the value it got, instead of an ``AttributeError`` deep
inside.  Annotations it cannot read as a runtime check (``Any``, type variables,
callables' signatures, element types of containers) are not checked: values are the
functions' own business (each validates its ranges and raises the project's errors).
"""

from __future__ import annotations

import collections.abc
import functools
import inspect
import numbers
import os
import sys
import types
import typing
from typing import Any, Callable

from .errors import InputError

__all__ = ["checked"]

_NONE = type(None)


def _short(value: Any) -> str:
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


def _is_bool(v: Any) -> bool:
    return isinstance(v, (bool, getattr(sys.modules.get("numpy"), "bool_", bool)))


def _is_sequence(v: Any) -> bool:
    return isinstance(v, (list, tuple)) or type(v).__name__ == "ndarray"


def _is_iterable(v: Any) -> bool:
    return isinstance(v, collections.abc.Iterable) and not isinstance(v, (str, bytes))


#: the predicates of plain annotations (after ``list[int] -> list``)
_PLAIN: dict[Any, Callable[[Any], bool]] = {
    _NONE: lambda v: v is None,
    None: lambda v: v is None,
    bool: _is_bool,
    int: lambda v: isinstance(v, numbers.Integral) and not isinstance(v, bool),
    float: lambda v: isinstance(v, numbers.Real) and not isinstance(v, bool),
    str: lambda v: isinstance(v, str),
    collections.abc.Sequence: _is_sequence, list: _is_sequence, tuple: _is_sequence,
    collections.abc.Iterable: _is_iterable, collections.abc.Collection: _is_iterable,
    collections.abc.Callable: callable,
    collections.abc.Mapping: lambda v: isinstance(v, collections.abc.Mapping),
    dict: lambda v: isinstance(v, collections.abc.Mapping),
    os.PathLike: lambda v: isinstance(v, os.PathLike),
}


def _check_for(annotation: Any) -> Callable[[Any], bool] | None:
    """A predicate for values of ``annotation``, or None when it is not checked at run time."""
    if annotation is Any or annotation is object or isinstance(annotation, typing.TypeVar):
        return None
    origin = typing.get_origin(annotation)
    if origin in (typing.Union, types.UnionType):
        parts = [_check_for(a) for a in typing.get_args(annotation)]
        if any(p is None for p in parts):
            return None
        return lambda v: any(p(v) for p in parts)
    if origin is typing.Literal:
        allowed = typing.get_args(annotation)
        return lambda v: any(v == a and type(v) is type(a) for a in allowed)
    if origin is not None:
        annotation = origin  # list[int] -> list, Sequence[str] -> Sequence, Callable[...] -> Callable
    if getattr(annotation, "__module__", "") == "typing" or getattr(annotation, "_is_protocol", False):
        return None  # typing.IO and friends, supcoord.bdd.BDD: protocols, not runtime classes
    try:
        plain = _PLAIN.get(annotation)
    except TypeError:  # an unhashable annotation: not a class
        plain = None
    if plain is not None:
        return plain
    if isinstance(annotation, type):
        return lambda v: isinstance(v, annotation)
    return None


def _describe(annotation: Any) -> str:
    text = getattr(annotation, "__name__", None) or str(annotation)
    return text.replace("typing.", "").replace("os.PathLike", "a path").replace("NoneType", "None")


def checked(func: Callable) -> Callable:
    """``func`` with its arguments checked against its annotations (module docstring)."""
    if not inspect.isfunction(func):
        return func
    try:
        hints = typing.get_type_hints(func)
    except Exception:  # noqa: BLE001 (a name only imported for type checkers: check what can be read)
        hints = {}
        module = sys.modules.get(func.__module__)
        for name, text in getattr(func, "__annotations__", {}).items():
            try:
                hints[name] = eval(text, vars(module)) if isinstance(text, str) else text  # noqa: S307
            except Exception:  # noqa: BLE001
                continue
    signature = inspect.signature(func)
    checks = {name: (pred, hints[name]) for name in signature.parameters
              if name in hints and (pred := _check_for(hints[name])) is not None}
    if not checks:
        return func

    @functools.wraps(func)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        try:
            bound = signature.bind(*args, **kwargs)
        except TypeError as exc:
            raise InputError(f"{func.__name__}(): {exc}", value=None) from None
        for name, value in bound.arguments.items():
            entry = checks.get(name)
            if entry is None:
                continue
            kind = signature.parameters[name].kind
            values = value if kind is inspect.Parameter.VAR_POSITIONAL else (
                value.values() if kind is inspect.Parameter.VAR_KEYWORD else (value,))
            for v in values:
                if not entry[0](v):
                    raise InputError(f"{func.__name__}(): {name} must be {_describe(entry[1])}, got "
                                     f"{type(v).__name__} {_short(v)}", value=v)
        return func(*args, **kwargs)

    wrapper.__supcoord_checked__ = True  # type: ignore[attr-defined]
    return wrapper
