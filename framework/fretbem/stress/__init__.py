"""Stresses on the boundary and inside the bodies: Somigliana, half-plane and closed forms.

``stresses(result, step, points, body)`` for one step; :class:`StressEvaluator` to reuse one
evaluation matrix over the steps; :func:`run_stress_request` for a scene file's
``[stress]`` table; :mod:`fretbem.stress.closed_form` for the half-plane closed forms.
"""

from fretbem.bem.stresses import StressOperator, StressSettings, somigliana_operator

from .errors import StressInputError, StressRequestError
from .evaluate import StressEvaluator, stresses
from .request import StressGrid, StressLine, StressRequest, stress_request_from_dict
from .result import StressResult
from .run import evaluate_stress_request, run_stress_request

__all__ = [
    "StressEvaluator",
    "StressGrid",
    "StressInputError",
    "StressLine",
    "StressOperator",
    "StressRequest",
    "StressRequestError",
    "StressResult",
    "StressSettings",
    "evaluate_stress_request",
    "run_stress_request",
    "somigliana_operator",
    "stress_request_from_dict",
    "stresses",
]
