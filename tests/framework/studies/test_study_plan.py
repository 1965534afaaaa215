"""The convergence study's plan checks what a user gives from Python before any run: a bad
value of any field, a family that is not installed, a pair count a family cannot place or a
budget the adaptive mode refuses is one InputError naming ``StudyPlan.field`` (and the
entry), where a run hours into the study used to fail, or ``repeats="3"`` ended in a
TypeError and ``memory="no"`` was true."""

from __future__ import annotations

import math

import numpy as np
import pytest

from fretbem.errors import InputError
from fretbem.studies.convergence import StudyPlan

SMALL = dict(families=(("nurbs", 2),), pairs=(15,), large_pairs=(), rest_pairs=(),
             adaptive_families=(("nurbs", 2),), budgets=(31,), sawtooth=())  # fmt: skip


@pytest.mark.parametrize(
    "field, bad, message",
    [
        ("pairs", 61, r"StudyPlan\.pairs must be a tuple of pair counts, got 61"),
        ("pairs", "15", r"StudyPlan\.pairs must be a tuple of pair counts, got the string"),
        ("pairs", ("15",), r"StudyPlan\.pairs\[0\] must be a whole number >= 1, got the str"),
        ("pairs", (15, 0), r"StudyPlan\.pairs\[1\] must be a whole number >= 1, got 0"),
        ("large_pairs", (15.5,), r"StudyPlan\.large_pairs\[0\] must be a whole number"),
        ("rest_pairs", (10**400,), r"StudyPlan\.rest_pairs\[0\] .*10\^400"),
        ("budgets", (True,), r"StudyPlan\.budgets\[0\] must be a whole number >= 1, got True"),
        ("rest_factors", (0.0,), r"StudyPlan\.rest_factors\[0\] must be > 0, got 0\.0"),
        ("rest_factors", ("2",), r"StudyPlan\.rest_factors\[0\] must be a number"),
        ("rest_factors", (math.nan,), r"StudyPlan\.rest_factors\[0\] must be a finite number"),
        ("families", (("nurbz", 2),), r"StudyPlan\.families\[0\]: unknown basis family 'nur"),
        ("families", ("nurbs",), r"StudyPlan\.families\[0\] must be a \(family name, degree\)"),
        ("families", (("nurbs", 2, 3),), r"StudyPlan\.families\[0\] must be a \(family name"),
        ("families", (("nurbs", 0),), r"StudyPlan\.families\[0\] degree must be a whole number"),
        ("adaptive_families", (("nurbs", "2"),), r"adaptive_families\[0\] degree must be a wh"),
        ("check_families", "nurbs", r"StudyPlan\.check_families must be a tuple of \(family"),
        ("repeats", 0, r"StudyPlan\.repeats must be a whole number >= 1, got 0"),
        ("repeats", "3", r"StudyPlan\.repeats must be a whole number >= 1, got the string"),
        ("memory", "no", r"StudyPlan\.memory must be True or False, got 'no'"),
        ("sawtooth", (31,), r"StudyPlan\.sawtooth must be \(first, last\), got \(31,\)"),
        ("sawtooth", (40, 31), r"StudyPlan\.sawtooth must have first <= last"),
        ("sawtooth", (31, "33"), r"StudyPlan\.sawtooth\[1\] must be a whole number"),
        ("tolerance", 0.0, r"StudyPlan\.tolerance must be > 0, got 0\.0"),
        ("tolerance", "1e-6", r"StudyPlan\.tolerance must be a number, got the string"),
    ],
)
def test_a_bad_field_is_refused_naming_it(field, bad, message):
    with pytest.raises(InputError, match=message) as caught:
        StudyPlan(**{**SMALL, field: bad})
    assert "give" in str(caught.value)  # a fix


@pytest.mark.parametrize(
    "change, message",
    [
        # lagrange2 puts 2 k + 1 points on the zone: 16 cannot be placed
        ({"families": (("lagrange2", None),), "pairs": (15, 16)},
         r"the run 'lagrange2, 16 pairs' cannot be built: .*exactly 16 collocation points"),
        ({"large_pairs": (16,), "families": (("lagrange2", None),)},
         r"the run 'lagrange2, 16 pairs, bodies x4' cannot be built"),
        ({"budgets": (31, 4)}, r"the run 'nurbs p=2 adaptive, budget 4' cannot be built"),
    ],
)  # fmt: skip
def test_a_run_the_plan_cannot_build_is_refused_before_any_run(change, message):
    with pytest.raises(InputError, match=message):
        StudyPlan(**{**SMALL, **change})


def test_valid_plans_keep_their_values():
    plan = StudyPlan(**{**SMALL, "pairs": np.array([15, 31]), "rest_factors": [np.float64(2)],
                        "repeats": np.int64(2), "memory": np.bool_(False),
                        "families": [["nurbs", np.int64(3)], ("lagrange2", None)]})  # fmt: skip
    assert plan.pairs == (15, 31) and all(type(n) is int for n in plan.pairs)
    assert plan.rest_factors == (2.0,) and plan.repeats == 2 and plan.memory is False
    assert plan.families == (("nurbs", 3), ("lagrange2", None))
    assert type(plan.families[0][1]) is int
    quick, full = StudyPlan.quick(), StudyPlan.full()
    assert quick.pairs == (15, 31) and quick.sawtooth == (31, 33) and quick.check_families
    assert full.check_families is None and len(full.cases()) > len(quick.cases())
