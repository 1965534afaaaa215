"""The reference Cattaneo-Mindlin fretting cycle (docs/theory.md) as a Scene record.

:class:`CattaneoMindlinScene` names the reference scene's parameters;
:func:`cattaneo_mindlin` turns them into the general :class:`~fretbem.scenes.spec.Scene`
(the record examples/cattaneo_mindlin.toml reads to) and builds it with the one scene
builder, :func:`fretbem.scenes.builder.build`, like any scene file.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from typing import Any

import attrs

from fretbem.basis import Basis
from fretbem.errors import InputError
from fretbem.geometry.shapes import CylinderPad, CylinderSpecimen, FlatSpecimen
from fretbem.material import Material
from fretbem.simulation import Simulation
from fretbem.solvers.newton import Solver
from fretbem.validators import (
    as_scalar,
    count_field,
    number_field,
    poisson_ratio,
    positive_field,
    real_number,
)
from fretbem.verification.closed_forms import HertzLineContact, MindlinDeresiewicz, dundurs_beta

from .builder import build, zone_elements
from .spec import BodySpec, ContactSpec, LoadSpec, MeshSpec, Scene

REFERENCE_STEPS = ("A", "B", "C", "D", "E")


def _loads(values: Any) -> tuple[float, ...]:
    """The tangential loads Q per step: finite numbers (True, strings refused), as floats."""
    where = "CattaneoMindlinScene.tangential"
    if isinstance(values, (str, bytes)) or not isinstance(values, Iterable):
        raise InputError(
            f"{where} must be a sequence of Q per step, got {values!r}; give Q in N/mm per step"
        )
    fix = "give Q in N/mm per step, e.g. (0, 18, 0, -18, 0)"
    return tuple(
        real_number(f"{where}[{k}]", as_scalar(q), what="Q, N/mm", fix=fix, error=InputError)
        for k, q in enumerate(values)
    )


_POISSON = number_field("Poisson's ratio", "give nu in (-1, 0.5)", check=poisson_ratio)


@attrs.frozen
class CattaneoMindlinScene:
    """Parameters of the reference scene (defaults are the scene file's values).

    Attributes
    ----------
    basis : str or Basis subclass
    pairs : int
        Node pairs in the candidate contact zone.
    zone : float
        Candidate zone half-width over the Hertz half-width.
    degree : int or None
        Basis degree (nurbs family); None for the family default.
    radius, width, height : float
        R, w, h in mm.
    lower : str
        "arc" (two similar bodies) or "flat" (pad on a flat specimen).
    E_upper, nu_upper, E_lower, nu_lower : float
    friction : float
    normal : float
        P, N/mm.
    tangential : sequence of float
        Q at the end of each step.
    names : sequence of str
    increments : int
        Sub-increments per step.
    flank_elements, side_elements, top_elements : int
        Elements on each flank, side and top/bottom.
    models : mapping of "upper"/"lower" to str
        Body model per body ("upper", "lower"): "bem" (default) or any name of the
        ``fretbem.bodies`` plugin group (``fretbem plugins``).
    """

    basis: str | type[Basis] = "nurbs"
    pairs: int = attrs.field(default=61, converter=count_field("give e.g. 61 (the default)"))
    zone: float = attrs.field(default=1.5, converter=positive_field("mm", "give e.g. 1.5"))
    degree: int | None = None
    radius: float = attrs.field(default=70.0, converter=positive_field("mm", "give e.g. 70"))
    width: float = attrs.field(default=6.5, converter=positive_field("mm", "give e.g. 6.5"))
    height: float = attrs.field(default=16.25, converter=positive_field("mm", "give e.g. 16.25"))
    lower: str = attrs.field(default="arc", validator=attrs.validators.in_(("arc", "flat")))
    E_upper: float = attrs.field(default=73400.0, converter=positive_field("MPa", "give E in MPa"))
    nu_upper: float = attrs.field(default=0.33, converter=_POISSON)
    E_lower: float = attrs.field(default=73400.0, converter=positive_field("MPa", "give E in MPa"))
    nu_lower: float = attrs.field(default=0.33, converter=_POISSON)
    friction: float = attrs.field(
        default=0.3,
        converter=number_field("the Coulomb coefficient f", "give f >= 0, e.g. 0.3", low=0.0),
    )
    normal: float = attrs.field(default=100.0, converter=positive_field("N/mm", "give P in N/mm"))
    tangential: Sequence[float] = attrs.field(
        default=(0.0, 18.0, 0.0, -18.0, 0.0), converter=_loads
    )
    names: Sequence[str] = attrs.field(default=REFERENCE_STEPS, converter=tuple)
    increments: int = attrs.field(default=1, converter=count_field("give e.g. 1 (the default)"))
    flank_elements: int = attrs.field(default=16, converter=count_field("give e.g. 16"))
    side_elements: int = attrs.field(default=12, converter=count_field("give e.g. 12"))
    top_elements: int = attrs.field(default=12, converter=count_field("give e.g. 12"))
    models: Mapping[str, str] = attrs.field(factory=dict, converter=lambda m: dict(m), hash=False)

    def __attrs_post_init__(self) -> None:
        if len(self.names) != len(self.tangential):
            raise ValueError(
                f"the scene has {len(self.names)} step names but {len(self.tangential)} "
                "tangential loads; give one name per load step"
            )

    def hertz(self) -> HertzLineContact:
        """Hertz line contact of the scene (two arcs, or arc on flat)."""
        return HertzLineContact.from_bodies(
            load=self.normal,
            radius_upper=self.radius,
            radius_lower=self.radius if self.lower == "arc" else math.inf,
            E_upper=self.E_upper,
            nu_upper=self.nu_upper,
            E_lower=self.E_lower,
            nu_lower=self.nu_lower,
        )

    def reference(self) -> MindlinDeresiewicz | None:
        """Mindlin-Deresiewicz reference, or None for dissimilar materials (coupled problem)."""
        beta = dundurs_beta(self.E_upper, self.nu_upper, self.E_lower, self.nu_lower)
        if abs(beta) > 1e-12:
            return None
        return MindlinDeresiewicz(self.hertz(), self.friction)

    def zone_elements(self, family: type[Basis]) -> int:
        """Elements on the zone segment giving exactly ``pairs`` collocation points."""
        return zone_elements(family, self.pairs, self.degree)

    def to_scene(self) -> Scene:
        """The same scene as the general :class:`~fretbem.scenes.spec.Scene` record (what
        examples/cattaneo_mindlin.toml reads to), which the one scene builder builds."""
        n = len(self.names)
        models = dict(self.models)
        shape = (
            CylinderSpecimen(self.radius, self.width, self.height)
            if self.lower == "arc"
            else FlatSpecimen(self.width, self.height)
        )
        return Scene(
            pad=BodySpec(CylinderPad(self.radius, self.width, self.height),
                         Material(self.E_upper, self.nu_upper), models.get("upper", "bem")),
            specimen=BodySpec(shape, Material(self.E_lower, self.nu_lower),
                              models.get("lower", "bem"), support="clamped-bottom"),
            contact=ContactSpec(friction=self.friction, basis=self.basis, degree=self.degree,
                                pairs=self.pairs, zone=self.zone),
            mesh=MeshSpec(self.flank_elements, self.side_elements, self.top_elements),
            load=LoadSpec(tuple(self.names), (self.normal,) * n, tuple(self.tangential),
                          (0.0,) * n, (self.increments,) * n),
        )  # fmt: skip


def cattaneo_mindlin(
    scene: CattaneoMindlinScene | None = None, *, solver: Solver | None = None, **overrides
) -> Simulation:
    """Build the reference fretting simulation (overrides are CattaneoMindlinScene fields).

    ``solver`` replaces the default :class:`~fretbem.solvers.newton.SemiSmoothNewton`; the body
    models come from ``scene.models`` (see :func:`body_model`).
    """
    # the defaults with the overrides in one construction (not the defaults' and an evolve)
    scene = CattaneoMindlinScene(**overrides) if scene is None else attrs.evolve(scene, **overrides)
    zone = scene.zone * scene.hertz().half_width
    if not 0 < zone < scene.width / 2:
        raise ValueError(
            f"the candidate zone half-width {zone:.4g} mm must lie inside the face (half-width "
            f"{scene.width / 2:g} mm); lower 'zone' or widen the bodies"
        )
    simulation, _ = build(scene.to_scene(), name="cattaneo-mindlin")
    return simulation if solver is None else attrs.evolve(simulation, solver=solver)
