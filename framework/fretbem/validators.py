"""Small attrs validators shared by the frozen records: finiteness, sign, shape."""

from __future__ import annotations

import math
import numbers
from collections.abc import Callable
from typing import Any

import attrs
import numpy as np

from .errors import InputError

#: the largest whole number a count may take: a 64-bit integer's (numpy's, a TOML file's)
WHOLE_MAX = 2**63 - 1


def as_float(value: Any) -> float:
    """``float(value)``, an int too large for a float read as +-infinity (refused as such)
    instead of Python's OverflowError."""
    try:
        return float(value)
    except OverflowError:
        return math.inf if value > 0 else -math.inf


def finite(instance: Any, attribute: Any, value: Any) -> None:
    """Reject NaN and infinite numbers (and ints too large for a float), naming the field."""
    if type(value) is float:  # the common scalar, without numpy's per-call cost
        ok = math.isfinite(value)
    else:
        # (the reduction called directly: ndarray.all's frame costs as much on a few numbers)
        try:
            ok = np.logical_and.reduce(np.isfinite(np.asarray(value, dtype=float)), axis=None)
        except OverflowError:
            ok = False
    if not ok:
        raise ValueError(
            f"{type(instance).__name__}.{attribute.name} must be finite, got {shown(value)}"
        )


def positive(instance: Any, attribute: Any, value: Any) -> None:
    """Require every entry to be finite and > 0."""
    finite(instance, attribute, value)
    if not (value > 0 if type(value) is float else np.all(np.asarray(value, dtype=float) > 0)):
        raise ValueError(f"{type(instance).__name__}.{attribute.name} must be > 0, got {value!r}")


def shape(*dims: int | None):
    """Validator requiring an array of the given shape (None matches any length)."""

    def check(instance: Any, attribute: Any, value: Any) -> None:
        arr = np.asarray(value)
        ok = arr.ndim == len(dims) and all(
            d is None or d == n for d, n in zip(dims, arr.shape, strict=False)
        )
        if not ok:
            want = "(" + ", ".join("n" if d is None else str(d) for d in dims) + ")"
            raise ValueError(
                f"{type(instance).__name__}.{attribute.name} must have shape {want}, "
                f"got {arr.shape}"
            )

    return check


def float_array(value: Any) -> np.ndarray:
    """Converter to a read-only float array, so frozen records stay frozen."""
    arr = np.array(value, dtype=float)
    arr.setflags(write=False)
    return arr


def poisson_ratio(where: str, value: float) -> None:
    """A number field's check (:func:`number_field`): a Poisson's ratio in (-1, 0.5), NaN
    refused."""
    if not (-1.0 < value < 0.5):
        raise InputError(
            f"{where}: Poisson's ratio nu must lie in (-1, 0.5) for a stable isotropic "
            f"material, got {value!r}; give e.g. 0.3 for a metal"
        )


def check_positive(name: str, value: float) -> float:
    """``value`` as a float; ValueError naming ``name`` unless finite and > 0 (plain calls)."""
    value = as_float(value)
    if not (math.isfinite(value) and value > 0.0):
        raise ValueError(f"{name} must be a finite number > 0, got {value!r}")
    return value


def check_poisson(name: str, value: float) -> float:
    """``value`` as a float; InputError (a ValueError) naming ``name`` unless a Poisson's ratio
    in (-1, 0.5)."""
    value = as_float(value)
    if not (math.isfinite(value) and -1.0 < value < 0.5):
        raise InputError(
            f"{name} must be a Poisson's ratio in (-1, 0.5), got {value!r}; "
            "give e.g. 0.3 for a metal"
        )
    return value


def real_number(
    where: str,
    value: Any,
    *,
    what: str,
    fix: str,
    infinite: bool = False,
    error: type[Exception] = ValueError,
) -> float:
    """A real number given from Python as a float: numpy scalars are taken, True/False and
    strings refused (no silent coercion), NaN (and infinity unless ``infinite``) refused.

    ``where`` names the argument (``Rig.pivot_height``), ``what`` says what it is (its unit),
    ``fix`` what to give instead; every message names all three.
    """
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        text = repr(value) if not isinstance(value, str) else f'"{value}" (a string)'
        raise error(f"{where} must be a number ({what}), got {text}; {fix}")
    number = as_float(value)
    if math.isnan(number) or (math.isinf(number) and not infinite):
        raise error(f"{where} must be a finite number ({what}), got {shown(value)}; {fix}")
    return number


def shown(value: Any) -> str:
    """A user's value as a message shows it: a string quoted, a huge int by its size."""
    if isinstance(value, int) and not isinstance(value, bool) and value.bit_length() > 64:
        # (repr of a huge int is hundreds of digits, and past 4300 digits Python refuses it)
        digits = int(value.bit_length() * math.log10(2))
        return f"an integer of about 10^{digits}"
    return f'the string "{value}"' if isinstance(value, str) else repr(value)


def as_scalar(value: Any) -> Any:
    """A 0-d numpy array of numbers as its number (``float()`` took it before); else as is."""
    if isinstance(value, np.ndarray) and value.ndim == 0 and value.dtype.kind in "iuf":
        return value.item()
    return value


def number_field(
    what: str,
    fix: str,
    *,
    none: bool = False,
    low: float | None = None,
    low_open: bool = False,
    high: float | None = None,
    check: Callable[[str, float], None] | None = None,
    error: type[Exception] = InputError,
) -> attrs.Converter:
    """Converter of a record's real-number field: numpy scalars and ints taken (as a float),
    True/False, strings and (unless ``none``) None refused, then NaN and infinity, then a
    value below ``low`` or above ``high``; or ``check(where, value)`` instead of the finite
    and range checks.

    Every message reads ``Record.field must be <want>, got <value> (<what>); <fix>``, the
    first words those of the finite/positive validators the records used before.
    """

    def convert(value: Any, instance: Any, field: Any) -> float | None:
        kind = type(value)
        if (kind is float or kind is int) and check is None:  # the common case, no frames
            number = as_float(value)
            if (
                math.isfinite(number)
                and (low is None or (number > low if low_open else number >= low))
                and (high is None or number <= high)
            ):
                return number
        if value is None and none:
            return None
        where = f"{type(instance).__name__}.{field.name}"
        given = value = as_scalar(value)

        def refuse(want: str) -> Exception:
            huge = isinstance(given, numbers.Integral) and value in (math.inf, -math.inf)
            text = shown(given if huge else value)
            return error(f"{where} must be {want}, got {text} ({what}); {fix}")

        if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
            raise refuse("a number")
        value = as_float(value)
        if not math.isfinite(value) and (check is None or isinstance(given, numbers.Integral)):
            raise refuse("finite")  # (an int past a float's range too, before any check)
        if check is not None:
            check(where, value)
            return value
        if low is not None and (value <= low if low_open else value < low):
            raise refuse(f"{'>' if low_open else '>='} {low:g}")
        if high is not None and value > high:
            raise refuse(f"<= {high:g}")
        return value

    return attrs.Converter(convert, takes_self=True, takes_field=True)


def positive_field(what: str, fix: str, *, error: type[Exception] = InputError) -> attrs.Converter:
    """:func:`number_field` of a finite number > 0 (a length, a load, a modulus)."""
    return number_field(what, fix, low=0.0, low_open=True, error=error)


def whole_number(
    where: str, value: Any, *, low: int, fix: str, error: type[Exception] = InputError
) -> int:
    """A whole number >= ``low`` given from Python as an int: numpy integers and integral
    floats (``2.0``) taken, True/False, strings and fractions (``2.5``) refused, and counts
    past a 64-bit integer (what numpy and a scene file can hold) too."""
    if type(value) is int and low <= value <= WHOLE_MAX:  # the common case (a bool's type differs)
        return value
    value = as_scalar(value)
    ok = not isinstance(value, bool) and isinstance(value, numbers.Real)
    if ok and not isinstance(value, numbers.Integral):
        ok = math.isfinite(as_float(value)) and float(value).is_integer()
    if not ok or int(value) < low:
        raise error(f"{where} must be a whole number >= {low}, got {shown(value)}; {fix}")
    if int(value) > WHOLE_MAX:
        raise error(f"{where} must be below 2^63 (a 64-bit count), got {shown(value)}; {fix}")
    return int(value)


def count_field(fix: str, *, low: int = 1, error: type[Exception] = InputError) -> attrs.Converter:
    """Converter of a record's whole-number field through :func:`whole_number`."""

    def convert(value: Any, instance: Any, field: Any) -> int:
        where = f"{type(instance).__name__}.{field.name}"
        return whole_number(where, value, low=low, fix=fix, error=error)

    return attrs.Converter(convert, takes_self=True, takes_field=True)


def flag(
    where: str,
    value: Any,
    *,
    none: bool = False,
    fix: str = "",
    error: type[Exception] = InputError,
) -> Any:
    """A yes/no argument given from Python: True or False (numpy's too; None where ``none``),
    nothing else: ``overwrite="no"`` would be true and overwrite."""
    if value is None and none:
        return None
    if not isinstance(value, (bool, np.bool_)):
        also = ", or None" if none else ""
        fix = f"; {fix}" if fix else ""
        raise error(f"{where} must be True or False{also}, got {value!r}{fix}")
    return bool(value)


def flag_field(fix: str, *, error: type[Exception] = InputError) -> attrs.Converter:
    """Converter of a record's yes/no field: True or False (numpy's too), nothing else
    (``"no"`` would be true)."""

    def convert(value: Any, instance: Any, field: Any) -> bool:
        if type(value) is bool:  # the common case, without the message's frame
            return value
        return flag(f"{type(instance).__name__}.{field.name}", value, fix=fix, error=error)

    return attrs.Converter(convert, takes_self=True, takes_field=True)


# -- values read from a file (TOML): strict, no coercion, the key named in every message -----
def _kind_error(error: type[Exception], where: str, want: str, value: Any) -> Exception:
    shown = repr(value) if not isinstance(value, str) else f'"{value}" (a string)'
    return error(f"{where} must be {want}, got {shown}")


def file_number(
    where: str,
    value: Any,
    *,
    low: float | None = None,
    high: float | None = None,
    low_open: bool = False,
    high_open: bool = False,
    why: str = "",
    error: type[Exception] = ValueError,
) -> float:
    """A finite number from a file (true/false and strings refused), within [low, high].

    ``where`` names the key as the user wrote it (``[fatigue] runout_cycles``); ``why`` is
    appended to a range message (the physical reason). Returns a float.
    """
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise _kind_error(error, where, "a number", value)
    if not math.isfinite(as_float(value)):  # (an int past a float's range: only from Python)
        raise error(f"{where} must be a finite number, got {shown(value)}")
    bad_low = low is not None and (value <= low if low_open else value < low)
    bad_high = high is not None and (value >= high if high_open else value > high)
    if bad_low or bad_high:
        parts = []
        if low is not None:
            parts.append(f"{'>' if low_open else '>='} {low:g}")
        if high is not None:
            parts.append(f"{'<' if high_open else '<='} {high:g}")
        reason = f" ({why})" if why else ""
        raise error(f"{where} must be {' and '.join(parts)}{reason}, got {value!r}")
    return float(value)


def file_integer(
    where: str,
    value: Any,
    *,
    low: int | None = None,
    high: int | None = None,
    why: str = "",
    error: type[Exception] = ValueError,
) -> int:
    """A whole number from a file (2.0, 2.7, true and "2" refused), within [low, high]."""
    if isinstance(value, bool) or not isinstance(value, int):
        raise _kind_error(error, where, "a whole number (no decimal point)", value)
    if abs(value) > WHOLE_MAX:  # (only from Python: a TOML file's integers are 64-bit)
        raise error(f"{where} must fit a 64-bit integer, got {shown(value)}")
    if (low is not None and value < low) or (high is not None and value > high):
        span = " and ".join(
            p for p in (f">= {low}" if low is not None else "", f"<= {high}" if high else "") if p
        )
        reason = f" ({why})" if why else ""
        raise error(f"{where} must be {span}{reason}, got {value!r}")
    return int(value)


def file_bool(where: str, value: Any, *, error: type[Exception] = ValueError) -> bool:
    """true or false from a file ("false", 0 and 1 refused: TOML has booleans)."""
    if not isinstance(value, bool):
        raise _kind_error(error, where, "true or false (no quotes)", value)
    return value


def file_string(
    where: str,
    value: Any,
    choices: tuple[str, ...] | None = None,
    *,
    error: type[Exception] = ValueError,
) -> str:
    """A string from a file, one of ``choices`` when given."""
    if not isinstance(value, str):
        want = "one of " + ", ".join(f'"{c}"' for c in choices) if choices else "a string"
        raise _kind_error(error, where, want, value)
    if choices is not None and value not in choices:
        raise error(f"{where} must be one of {', '.join(repr(c) for c in choices)}, got {value!r}")
    return value


def file_list(
    where: str,
    value: Any,
    item,
    *,
    length: int | None = None,
    min_length: int = 0,
    error: type[Exception] = ValueError,
) -> list:
    """A list from a file, each entry checked by ``item(where[k], entry)``."""
    if not isinstance(value, list):
        raise _kind_error(error, where, "a list", value)
    if length is not None and len(value) != length:
        raise error(f"{where} must be a list of {length} entries, got {value!r}")
    if len(value) < min_length:
        raise error(f"{where} needs at least {min_length} entries, got {value!r}")
    return [item(f"{where}[{k}]", v) for k, v in enumerate(value)]
