"""jointflow.Tracker's keywords: made from the core's settings schema, typed, checked with the
core's messages."""

import os
import pathlib

import numpy as np
import pytest

import jointflow


def test_schema_lists_every_setting_with_its_default():
    rows = jointflow.settings()
    names = [r.name for r in rows]
    assert len(names) == len(set(names)) >= 25
    for expected in ("similarity", "matcher", "input_size", "tau_delta", "min_track_length",
                     "lost_time", "reid", "output_tentative", "backend", "num_threads"):
        assert expected in names
    by_name = {r.name: r for r in rows}
    assert by_name["similarity"].type is str and "tff" in by_name["similarity"].choices
    assert by_name["tau_delta"].type is float and by_name["tau_delta"].range == (0.0, 1000.0)
    assert by_name["min_track_length"].type is int and by_name["min_track_length"].default == 7
    assert by_name["smoothing"].type is bool and by_name["smoothing"].default is False
    assert by_name["min_potential"].default == 0.1  # float32 0.1f shown as 0.1
    assert all(r.doc for r in rows)
    # The Tracker's docstring lists them too.
    assert "tau_delta: float = 12.0" in jointflow.Tracker.__doc__


def test_defaults_and_values_in_force():
    defaults = {r.name: r.default for r in jointflow.settings()}
    assert jointflow.Tracker().settings == defaults
    tracker = jointflow.Tracker(similarity="iou", matcher="optimal", tau_delta=3, lost_time=1.5,
                                min_track_length=np.int64(4), smoothing=True,
                                input_size="256x256", reid="off")
    s = tracker.settings
    assert (s["similarity"], s["matcher"], s["reid"]) == ("iou", "optimal", "off")
    assert s["tau_delta"] == 3.0 and s["lost_time"] == 1.5 and s["min_track_length"] == 4
    assert s["smoothing"] is True and s["input_size"] == "256x256"


def test_tiles_takes_its_names_and_the_bools_it_took_before():
    # tiles was a bool before auto (the default) came: True and False still choose on and off.
    assert jointflow.Tracker().settings["tiles"] == "auto"
    assert jointflow.Tracker(tiles=True, tile_size=512).settings["tiles"] == "true"
    assert jointflow.Tracker(tiles=False).settings["tiles"] == "false"
    assert jointflow.Tracker(tiles="false").settings["tiles"] == "false"
    with pytest.raises(ValueError, match="auto, true or false"):
        jointflow.Tracker(tiles="sometimes")
    with pytest.raises(TypeError, match="auto, true or false"):
        jointflow.Tracker(tiles=1)
    # Only where the names are there: other choices still ask for a str.
    with pytest.raises(TypeError, match="a str"):
        jointflow.Tracker(similarity=True)


def test_paths_may_be_pathlike():
    models = os.environ.get("JOINTFLOW_MODELS_DIR") or pathlib.Path(__file__).parents[2] / "models"
    path = pathlib.Path(models) / "movenet_multipose.onnx"
    tracker = jointflow.Tracker(spatial_model=path)
    assert tracker.settings["spatial_model"] == str(path)


def test_unknown_keyword_lists_the_valid_ones():
    with pytest.raises(TypeError) as e:
        jointflow.Tracker(tau=2.0)
    message = str(e.value)
    assert "unknown setting 'tau'" in message
    for name in ("tau_delta", "similarity", "input_size", "min_track_length"):
        assert name in message
    with pytest.raises(TypeError, match="unknown setting 'tau-delta'"):
        jointflow.Tracker(**{"tau-delta": 2.0})


@pytest.mark.parametrize("kwargs, expected", [
    ({"tau_delta": "2"}, "tau_delta expects a float, got str '2'"),
    ({"tau_delta": True}, "tau_delta expects a float, got bool True"),
    ({"min_track_length": 2.5}, "min_track_length expects an int, got float 2.5"),
    ({"min_track_length": True}, "min_track_length expects an int"),
    ({"smoothing": 1}, "smoothing expects True or False, got int 1"),
    ({"similarity": 3}, "similarity expects a str, one of tff, oks, iou, pckh, flow or auto, got int 3"),
    ({"input_size": (256, 256)}, "input_size expects a str"),
    ({"spatial_model": None}, "spatial_model expects a str, got NoneType None"),
])
def test_wrong_types(kwargs, expected):
    with pytest.raises(TypeError) as e:
        jointflow.Tracker(**kwargs)
    assert expected in str(e.value)


# The messages are the core's (checkSettingValue, parseSettingEnum, the parsers of the rows and
# the Tracker constructor), unchanged.
@pytest.mark.parametrize("kwargs, message", [
    ({"tau_delta": 2000.0}, "tau-delta: 2000 is out of range (0 to 1000)"),
    ({"tau_delta": -1}, "tau-delta: -1 is out of range (0 to 1000)"),
    ({"tau_delta": float("nan")}, "tau-delta: nan is out of range (0 to 1000)"),
    ({"min_track_length": 0}, "min-track-length: 0 is out of range (1 to 100000)"),
    ({"min_track_length": 10**30}, f"min-track-length: {10**30} is out of range (1 to 100000)"),
    ({"person_threshold": 1.5}, "person-threshold: 1.5 is out of range (0 to 1)"),
    ({"max_persons": 0}, "max-persons: 0 is out of range (1 to 1000)"),
    ({"similarity": "tf"}, "similarity: unknown similarity 'tf', expected tff, oks, iou, pckh, flow or auto"),
    ({"reid": "colour"}, "reid: unknown appearance model 'colour', expected off, features or features-colour"),
    ({"matcher": "Greedy"}, "matcher: unknown matcher 'Greedy', expected greedy or optimal"),
])
def test_values_out_of_range_and_unknown_names(kwargs, message):
    with pytest.raises(ValueError) as e:
        jointflow.Tracker(**kwargs)
    assert str(e.value) == message


def test_text_the_core_cannot_parse():
    with pytest.raises(ValueError, match="input"):
        jointflow.Tracker(input_size="big")
    with pytest.raises(ValueError) as e:
        jointflow.Tracker(scales="1,x")
    assert str(e.value) == ('scales: "x" in "1,x" is not a scale in (0, 4]; expected e.g. "1" or '
                            '"0.5,1,1.5"')


def test_combinations_are_checked_by_the_tracker(tmp_path):
    missing = tmp_path / "no_tff.onnx"
    with pytest.raises(ValueError) as e:
        jointflow.Tracker(similarity="tff", tff_model=str(missing))
    assert str(e.value).startswith('similarity "tff" needs a TFF model for the movenet spatial model, but ' + str(missing))
    with pytest.raises(ValueError) as e:
        jointflow.Tracker(spatial_model=str(tmp_path / "none.onnx"))
    assert "none.onnx" in str(e.value)
