"""Hostile sweeps by class: what the sweep solves is what the scene says (swept [fatigue]
keys, adaptive meshes), everything checkable is checked before any case is solved (maps,
outputs, values, size), and the store cannot be mixed (lock, per-chunk checksums)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from fretbem.errors import InputError
from fretbem.output.staging import OutputLockedError, output_lock
from fretbem.studies.sweep.run import MAX_CASES, SweepError, run_command, sweep
from fretbem.studies.sweep.spec import SweepSpec, SweepSpecError
from fretbem.studies.sweep.store import SweepStoreError, read_table

SCENE = {
    "pad": {"shape": "cylinder", "radius": 70.0},
    "specimen": {"shape": "cylinder"},
    "contact": {"pairs": 11},
    "load": {"steps": ["A", "B"], "P": 100.0, "Q": [0.0, 18.0]},
}


def _sweep(tmp_path, parameters, name="store", **options):
    return sweep(SCENE, parameters, out=tmp_path / name, serial=True, progress=False, **options)


def test_swept_fatigue_keys_win_over_the_sweep_files_table():
    """Reproducer: [fatigue] of the sweep file replaced the swept coefficient: equal lives."""
    table = {"material": "Ti-6Al-4V", "constants": {"fatigue_strength_coefficient": 1500.0}}
    spec = SweepSpec.from_mapping(
        SCENE,
        {"fatigue.constants.fatigue_strength_coefficient": [1000.0, 2464.0]},
        fatigue=table,
    )
    got = [c.scene["fatigue"]["constants"]["fatigue_strength_coefficient"] for c in spec.cases()]
    assert got == [1000.0, 2464.0]
    assert all(c.scene["fatigue"]["material"] == "Ti-6Al-4V" for c in spec.cases())


def test_an_adaptive_scene_is_solved_adaptively_in_a_sweep(tmp_path):
    """Reproducer: a sweep of mesh = 'adaptive' solved the fixed 61-pair mesh."""
    scene = {**SCENE, "contact": {"mesh": "adaptive", "budget": 21, "tolerance": 0.05}}
    result = sweep(scene, {"contact.friction": [0.3, 0.4]}, out=tmp_path / "a", serial=True)
    table = result.table
    assert set(table["status"]) == {"ok"}
    assert all(5 <= p <= 21 and p != 61 for p in table["pairs"])


@pytest.mark.parametrize(
    ("maps", "words"),
    [
        ({"x": "load.P", "y": "contact.friction", "column": "stick_widht.B"}, "stick_widht.B"),
        ({"x": "load.P", "y": "load.Q"}, "'load.Q' is not a varied parameter"),
        ({"x": "load.P", "y": "contact.friction", "colour": "red"}, "unknown keys"),
        ({"x": "load.P", "y": "contact.friction", "where": {"load.Q": 1}}, "'load.Q'"),
    ],
)
def test_map_mistakes_are_refused_before_any_case_is_solved(tmp_path, maps, words):
    with pytest.raises(SweepSpecError, match=words):
        _sweep(tmp_path, {"load.P": [90.0, 100.0], "contact.friction": [0.3, 0.4]},
               options={"maps": [maps]})  # fmt: skip
    assert not list((tmp_path / "store").glob("cases-*"))


@pytest.mark.parametrize("name", ["os:getcwd", "builtins:print", "fretbem:run", "nope"])
def test_only_registered_outputs_run(tmp_path, name):
    with pytest.raises(SweepSpecError, match="not a registered sweep output"):
        _sweep(tmp_path, {"load.P": [90.0]}, outputs=[name])


@pytest.mark.parametrize(
    ("path", "value", "words"),
    [
        ("contact.pairs", True, "must be an integer, got True"),
        ("contact.pairs", 11.5, "must be an integer"),
        ("contact.friction", -0.3, "friction must be > 0"),
        ("fatigue.constants.fatigue_strength_exponent", 0.5, "physical range"),
    ],
)
def test_bad_values_are_refused_before_solving_naming_the_parameter(tmp_path, path, value, words):
    parameters = {path: [value]}
    options = {"fatigue": {"material": "Ti-6Al-4V"}} if path.startswith("fatigue") else {}
    with pytest.raises(SweepSpecError, match=rf"'{path}' = .*{words}"):
        _sweep(tmp_path, parameters, options=options)


@pytest.mark.parametrize(
    ("path", "values", "words"),
    [
        ("contact.friction", [0.5, True], "must be .*got True"),
        ("contact.pairs", [11, 11.0], "must be an integer, got 11.0"),
        ("load.moment", [1.0, True], "moment must be .*got True"),
    ],
)
def test_a_bad_value_equal_to_a_good_one_is_still_checked(tmp_path, path, values, words):
    """Reproducer: the value check kept one of each equal value (true == 1, 11.0 == 11), so
    [0.5, true] or [11, 11.0] reached the cases and failed there as error rows."""
    with pytest.raises(SweepSpecError, match=rf"'{path}' = .*{words}"):
        _sweep(tmp_path, {path: values})


def test_a_huge_sweep_is_refused_with_its_size():
    parameters = {"load.P": {"start": 50.0, "stop": 150.0, "num": 1000},
                  "contact.friction": {"start": 0.2, "stop": 0.6, "num": 1000}}  # fmt: skip
    with pytest.raises(SweepError, match=r"1000 x 1000 = 1000000 cases"):
        sweep(SCENE, parameters, out="unused", serial=True)
    assert MAX_CASES < 10**6


def test_the_store_is_locked_and_its_chunks_checked(tmp_path):
    parameters = {"load.P": [90.0, 100.0]}
    _sweep(tmp_path, parameters, batch=1)
    store = tmp_path / "store"
    with output_lock(store.resolve()), pytest.raises(OutputLockedError, match="another"):
        _sweep(tmp_path, parameters)  # a second sweep while the first holds the store
    first, second = sorted(store.glob("cases-*.parquet"))
    import pandas as pd

    frame = pd.read_parquet(first)
    frame["p_max.B"] *= 2
    frame.to_parquet(first)  # rewritten by hand
    with pytest.raises(SweepStoreError, match=rf"{first.name} was changed"):
        read_table(store)
    first.write_bytes(b"garbage")
    with pytest.raises(SweepStoreError, match=first.name):
        _sweep(tmp_path, parameters)
    first.unlink()
    (store / (first.name + ".sha256")).unlink()
    foreign = store / "cases-0000009-0000009-feedbeef.parquet"
    foreign.write_bytes(second.read_bytes())  # copied in, without a checksum of its own
    with pytest.raises(SweepStoreError, match=rf"{foreign.name}: no valid checksum"):
        _sweep(tmp_path, parameters)
    foreign.unlink()
    again = _sweep(tmp_path, parameters)  # the deleted chunk's case is solved again
    assert again.summary.solved_now == 1 and len(again.table) == 2


def test_maps_are_redrawn_from_a_store_and_not_part_of_its_identity(tmp_path):
    """Reproducer: fixing a [[maps]] typo was refused as 'another sweep'."""
    sweep_file = tmp_path / "map.toml"
    scene = tmp_path / "scene.toml"
    scene.write_text(
        '[pad]\nshape = "cylinder"\n[specimen]\nshape = "cylinder"\n[contact]\npairs = 11\n'
        '[load]\nsteps = ["A", "B"]\nP = 100.0\nQ = [0.0, 18.0]\n'
    )
    body = '[sweep]\nscene = "scene.toml"\n[parameters]\n"load.P" = [90.0, 100.0]\n'
    sweep_file.write_text(body)
    args = _args(sweep_file, tmp_path / "out")
    assert run_command(args) == 0
    assert (tmp_path / "out" / "map-regime-load_P.png").is_file()  # one parameter: a line
    sweep_file.write_text(body + '[[maps]]\nx = "load.P"\ncolumn = "stick_width.B"\n')
    args.maps_only = True
    assert run_command(args) == 0
    assert (tmp_path / "out" / "map-stick_width_B-load_P.png").is_file()


def _args(path, out):
    import argparse

    return argparse.Namespace(
        sweep_file=str(path), scheduler=None, serial=True, out=str(out), workers=None,
        batch=None, limit=None, no_figures=False, maps_only=False,
    )  # fmt: skip


def test_errors_are_input_errors():
    assert issubclass(SweepSpecError, InputError)
    assert math.isfinite(float(np.float64(1.0)))
