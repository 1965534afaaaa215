"""Segments that are each other's point image (reflected through the origin), for the block store.

The Kelvin kernels are even in the offset and the normal together: T(-r, -n) = T(r, n) and
U(-r) = U(r), each product and sum of their formulas the same floating-point operation on
negated operands. A segment whose geometry is the exact point image of another's (the same
family, parameterisation and functions, its coefficients negated) has, against the image of
any other segment, the same regular H and G blocks to the last bit, and its quadrature rules
are the other's with points, tangents and normals negated. Two similar cylinders (the
reference scene's pad and specimen, :mod:`fretbem.geometry.shapes`) are such images: one
body's discretisation (:func:`discretise`), collocation points
(:class:`fretbem.bem.integration.Collocation`), rules and blocks
(:class:`fretbem.bem.assembly.BlockStore`) serve the other's.
"""

from __future__ import annotations

import hashlib
import weakref

import attrs
import numpy as np

from fretbem.basis import Basis, Refinement
from fretbem.geometry.nurbs import NurbsCurve

#: the fields of a Basis and of its curve that carry the geometry (negated in an image)
GEOMETRY_FIELDS = frozenset({"geometry_coefficients", "control_points"})


def signatures(basis: Basis) -> tuple[bytes, bytes] | None:
    """Digests (the segment's, its point image's) of every field of the segment and of its
    curve, equal between a segment and any exact copy, so that ``signatures(a)[1] ==
    signatures(b)[0]`` when b is a's point image; None when the family's map is not odd in
    the geometry (``Basis.odd_in_geometry``)."""
    if not type(basis).odd_in_geometry:
        return None
    return _digests(basis)


def _digests(record) -> tuple[bytes, bytes]:
    """The digests of ``record`` and of its point image, from one walk over its fields: the
    fields the reflection keeps hashed once, the geometry hashed as it is and negated."""
    common, geometry = [], []
    _walk(record, common, geometry)
    kept = hashlib.blake2b(b"".join(common), digest_size=20).digest()
    out = []
    for sign in (1.0, -1.0):
        digest = hashlib.blake2b(kept, digest_size=20)
        for value in geometry:
            digest.update((sign * value + 0.0).tobytes())  # + 0.0: -0.0 is 0.0
        out.append(digest.digest())
    return out[0], out[1]


def _walk(record, common: list, geometry: list) -> None:
    common.append(type(record).__qualname__.encode())
    for field in attrs.fields(type(record)):
        value = getattr(record, field.name)
        common.append(field.name.encode())
        if attrs.has(type(value)):
            _walk(value, common, geometry)
        elif isinstance(value, np.ndarray):
            common.append(f"{value.dtype.str}{value.shape}".encode())
            if field.name in GEOMETRY_FIELDS:
                geometry.append(np.ascontiguousarray(value))
            else:
                common.append(np.ascontiguousarray(value).tobytes())
        else:
            common.append(f"{type(value).__qualname__}:{value!r}".encode())


#: the rules (:func:`fretbem.bem.assembly._segment_rules`) that are points, tangents or
#: normals: negated in the image; per key, the entries of a tuple that are (None: the array)
NEGATED = {
    "far": (0, 1),
    "mid": (0, 1),
    "samples": None,
    "centres": None,
    "start_points": None,
    "start_tangents": None,
    "singular_sides": (0, 1),
}


def _negated(array: np.ndarray) -> np.ndarray:
    """-array, its zeros +0 (as a point image's own evaluation gives them, and as printed)."""
    return -array + 0.0


def reflected_rules(rules: dict) -> dict:
    """A segment's rules for its point image: points, tangents and normals negated (exactly
    what the image's own basis evaluation gives), weights, values and lengths shared."""
    out = dict(rules)
    for name, entries in NEGATED.items():
        value = rules[name]
        if hasattr(value, "reflected"):  # evaluated when used (assembly.SingularRules)
            out[name] = value.reflected()
        elif entries is None:
            out[name] = _negated(value)
        else:
            out[name] = tuple(_negated(v) if i in entries else v for i, v in enumerate(value))
    return out


#: discretised segments by (family, refinement, curve) digest, so that a curve's point image
#: finds the segment discretised before (weak values: it goes with the segment)
_DISCRETISED: weakref.WeakValueDictionary = weakref.WeakValueDictionary()
#: each segment discretised as another's point image: that other segment (weak both ways)
_SOURCES: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def discretise(family: type[Basis], curve, refinement: Refinement) -> Basis:
    """``family.discretise(curve, refinement)``; for the point image of a curve discretised
    before by the same family and refinement, that segment reflected (the same numbers, when
    the family is odd in the geometry: ``Basis.odd_in_geometry``)."""
    if not family.odd_in_geometry:
        return family.discretise(curve, refinement)
    how = f"{family.__module__}.{family.__qualname__}:{refinement!r}".encode()
    own, image = (how + digest for digest in _digests(curve))
    source = _DISCRETISED.get(image)
    if source is None:
        basis = family.discretise(curve, refinement)
    else:
        curve = source.curve
        if type(curve) is NurbsCurve:  # the checked curve's arrays negated: valid as they are
            image = NurbsCurve.exact_image(
                curve, curve.knots, _negated(curve.control_points), curve.weights
            )
        else:
            image = attrs.evolve(curve, control_points=_negated(curve.control_points))
        basis = _reflected(source, image)
        _SOURCES[basis] = weakref.ref(source)
    _DISCRETISED[own] = basis
    return basis


#: the fields of a plain :class:`~fretbem.basis.Basis` (a family adding none is copied
#: field by field in :func:`_reflected`)
_BASIS_FIELDS = tuple(field.name for field in attrs.fields(Basis))


def _reflected(source: Basis, curve) -> Basis:
    """``attrs.evolve(source, curve=curve, geometry_coefficients=-coefficients)``: for a
    family with the plain Basis fields and no post-init, the checked read-only arrays of
    ``source`` shared and only the negated coefficients new (no converter or validator runs
    again on arrays that passed them); any other family through ``attrs.evolve``."""
    kind = type(source)
    coefficients = _negated(source.geometry_coefficients)
    if (
        tuple(field.name for field in attrs.fields(kind)) != _BASIS_FIELDS
        or getattr(kind, "__attrs_post_init__", None) is not None
    ):
        return attrs.evolve(source, curve=curve, geometry_coefficients=coefficients)
    coefficients.setflags(write=False)
    basis = object.__new__(kind)
    for name in _BASIS_FIELDS:
        object.__setattr__(basis, name, getattr(source, name))
    object.__setattr__(basis, "curve", curve)
    object.__setattr__(basis, "geometry_coefficients", coefficients)
    return basis


def source(basis: Basis) -> Basis | None:
    """The segment ``basis`` was discretised from as its point image (:func:`discretise`),
    if it is alive, else None."""
    ref = _SOURCES.get(basis)
    return None if ref is None else ref()
