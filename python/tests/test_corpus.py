"""The CLI's bad-input corpus (crates/opalray-cli/tests/bad_inputs/cases.txt) walked from
Python: every case with a Python equivalent (a scene file, a flag that sets a scene field,
an unknown preset) raises a one-line ``ValueError`` naming the field or argument, never a
Rust panic (``PanicException``, which is not an ``Exception`` and fails the test)."""

from __future__ import annotations

import math
import tomllib

import pytest

import opalray
from conftest import REPO

CASES = REPO / "crates" / "opalray-cli" / "tests" / "bad_inputs" / "cases.txt"

# The command's flags that set one scene field, and the field.
FLAG_FIELDS = {
    "--width": "render.width",
    "--height": "render.height",
    "--diameter": "crystal.sphere_diameter_nm",
    "--bins": "spectrum.bins",
    "--rays": "light.rays",
    "--cutoff": "light.cutoff",
    "--body-tone": "render.body_tone",
    "--exposure": "color.exposure_ev",
    "--spp": "integrator.spp",
    "--tilt": "camera.tilt_deg",
    "--light-angle": "light.angle_deg",
}

# Flags that only size the run (not the scene's fields): dropped from a case's arguments.
TINY = ["--width", "8", "--height", "6", "--rays", "64"]


def _cases() -> list[tuple[str, list[str], str, str]]:
    """(line, args, file, expected) of every case that succeeds nowhere (exit code 2)."""
    out = []
    for line in CASES.read_text(encoding="utf-8").splitlines():
        code, env, args, file, expected = (part.strip() for part in line.split(" | ", 4))
        if code == "2" and env == "-":
            out.append((line, args.split(" "), file, expected))
    return out


def _value(text: str):
    """A flag's text as the Python value a user would pass."""
    if text == "''":
        return ""
    for kind in (int, float):
        try:
            return kind(text)
        except ValueError:
            pass
    return text


def _scene_file_cases():
    """Cases whose one input is a scene file `s.toml` rendered with only the size flags."""
    for line, args, file, expected in _cases():
        if args[:2] == ["render", "s.toml"] and args[2:] == TINY and file.startswith("s.toml:"):
            if " & " in file or "environment" in file:
                continue  # a map beside it: the error is the map's, at render
            text = file.split(":", 1)[1].replace("\\n", "\n")
            yield pytest.param(text, expected, id=line)


def _flag_cases():
    """Cases that set one field by its flag, on the default scene."""
    for line, args, file, expected in _cases():
        if file != "-" or len(args) != 3 or args[0] != "render" or args[1] not in FLAG_FIELDS:
            continue
        yield pytest.param(FLAG_FIELDS[args[1]], _value(args[2]), id=line)


def _one_line(err: pytest.ExceptionInfo) -> str:
    message = str(err.value)
    assert "\n" not in message, message
    return message


@pytest.mark.parametrize("text, expected", list(_scene_file_cases()))
def test_a_bad_scene_file_is_a_value_error_naming_the_field(text, expected):
    with pytest.raises(ValueError) as err:
        opalray.Scene.from_toml_str(text, "s.toml")
    assert expected in _one_line(err)
    # The same scene as a dict, where TOML's values are Python's.
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError:
        return
    with pytest.raises(ValueError) as err:
        opalray.Scene(data)
    assert expected in _one_line(err)


@pytest.mark.parametrize("field, value", list(_flag_cases()))
def test_a_bad_flag_value_is_a_value_error_naming_its_field(field, value):
    with pytest.raises(ValueError) as err:
        opalray.Scene.preset("paper").replace({field: value})
    message = _one_line(err)
    assert field in message, message
    assert "--" not in message.replace("—", ""), f"speaks of a flag: {message}"


def test_the_corpus_twin_covers_the_scene_fields_and_flags():
    # Guards the walk itself: a change of the corpus's format must not leave it empty.
    assert len(list(_scene_file_cases())) >= 400
    assert len(list(_flag_cases())) >= 40
    assert math.isnan(_value("nan")) and _value("''") == ""


@pytest.mark.parametrize("name", ["nosuch", "nope", "", "PAPER "])
def test_an_unknown_preset_names_the_argument_not_the_flag(name):
    with pytest.raises(ValueError) as err:
        opalray.Scene.preset(name)
    message = _one_line(err)
    assert "Scene.preset(name)" in message and "--preset" not in message, message
