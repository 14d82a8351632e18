"""The scene dict: the TOML schema, round trips, `replace`, and the CLI's bad-input corpus as
`ValueError`s naming the field."""

import math
import pickle

import pytest

import opalray
from conftest import REPO


def test_preset_is_the_shipped_paper_file():
    assert opalray.Scene.preset("paper") == opalray.Scene.from_toml(REPO / "scenes" / "paper.toml")
    # Nothing named: the preset every command renders.
    assert opalray.Scene() == opalray.Scene.preset() == opalray.Scene.preset(opalray.DEFAULT_PRESET)


def test_dict_round_trips_through_toml(tmp_path):
    scene = opalray.Scene.preset("paper").replace(crystal={"sphere_diameter_nm": 215.5})
    d = scene.to_dict()
    assert set(d) == {
        "structure", "crystal", "spectrum", "light", "camera", "render", "color",
        "domains", "body", "environment", "integrator",
    }
    path = tmp_path / "s.toml"
    scene.save(path)
    back = opalray.Scene.from_toml(path)
    assert back == scene and back.to_dict() == d
    assert opalray.Scene(d) == scene
    assert opalray.Scene.from_toml_str(scene.to_toml()) == scene
    assert pickle.loads(pickle.dumps(scene)) == scene


def test_a_map_is_taken_from_the_scene_files_folder(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text(
        '[integrator]\nmethod = "path"\n[environment]\nkind = "file"\npath = "studio.hdr"\n',
        encoding="utf-8",
    )
    scene = opalray.Scene.from_toml(path)
    assert scene["environment"]["path"] == str(tmp_path / "studio.hdr")
    text = path.read_text(encoding="utf-8")
    assert opalray.Scene.from_toml_str(text)["environment"]["path"] == "studio.hdr"


def test_partial_dict_takes_the_defaults():
    scene = opalray.Scene({"render": {"width": 100}})
    d = scene.to_dict()
    assert d["render"]["width"] == 100
    # As in a scene file: the fields' defaults, those of the paper's scene.
    assert d["render"]["height"] == opalray.Scene.preset("paper")["render"]["height"]
    assert opalray.Scene({}) == opalray.Scene.preset("paper")


def test_replace_merges_sections_and_dotted_paths():
    base = opalray.Scene.preset("paper")
    a = base.replace(crystal={"sphere_diameter_nm": 215})
    b = base.replace({"crystal.sphere_diameter_nm": 215})
    c = base.replace(**{"crystal.sphere_diameter_nm": 215.0})
    assert a == b == c
    assert a["crystal"]["sphere_diameter_nm"] == 215.0
    assert a["crystal"]["n_sphere"] == base["crystal"]["n_sphere"]
    assert base["crystal"]["sphere_diameter_nm"] != 215  # the original is unchanged
    # numpy scalars are numbers
    np = pytest.importorskip("numpy")
    assert base.replace(render={"width": np.int64(64)})["render"]["width"] == 64


# (dict changes, the field the error must name): the cases of crates/opalray-cli/tests
# (cli_structure.rs, cli_render.rs) and the core's scene tests, as a dict user writes them.
BAD = [
    ({"structure": {"void_ratoi": 0.3}}, "structure.void_ratoi"),
    ({"render": {"widht": 3}}, "render.widht"),
    ({"structure": {"grid": [100, 0, 25]}}, "structure.grid"),
    ({"structure": {"grid": [100, -75, 25]}}, "structure.grid"),
    ({"structure": {"semi_axes_mm": [10.0, 0.0, 2.5]}}, "structure.semi_axes_mm"),
    ({"structure": {"void_ratio": math.nan}}, "structure.void_ratio"),
    ({"structure": {"mean_radius_cells": math.nan}}, "structure.mean_radius_cells"),
    ({"structure": {"void_ratio": 1.5}}, "structure.void_ratio"),
    ({"structure": {"orientation_jitter_deg": -3.0}}, "structure.orientation_jitter_deg"),
    ({"structure": {"grid": [100000, 100000, 100000]}}, "structure.grid"),
    ({"render": {"width": 0}}, "render.width"),
    ({"render": {"width": "wide"}}, "render.width"),
    ({"render": {"body_tone": 12}}, "render.body_tone"),
    ({"light": {"angle_deg": math.nan}}, "light.angle_deg"),
    ({"light": {"rays": 0}}, "light.rays"),
    ({"light": {"cutoff": 0.0}}, "light.cutoff"),
    ({"light": {"cutoff": -0.1}}, "light.cutoff"),
    ({"crystal": {"sphere_diameter_nm": -250.0}}, "crystal.sphere_diameter_nm"),
    ({"crystal": {"n_sphere": 0.9}}, "crystal.n_sphere"),
    ({"colour": {"exposure_ev": 1}}, "colour"),
    ({"render": {"width": 1 << 70}}, "render.width"),
    ({"render": {"width": object()}}, "render.width"),
    ({"integrator": {"denoise": True}}, "integrator.denoise"),
    ({"domains": {"stretch": [1.0, 2.0, 3.0, 4.0]}}, "domains.stretch"),
    ({"domains": {"stretch": [1.0, 2.0]}}, "domains.stretch"),
    ({"light": {"size_mm": [10.0, 20.0, 30.0]}}, "light.size_mm"),
]


@pytest.mark.parametrize("changes, field", BAD, ids=[f for _, f in BAD])
def test_bad_values_are_value_errors_naming_the_field(changes, field):
    with pytest.raises(ValueError) as err:
        opalray.Scene(changes)
    message = str(err.value)
    assert field in message, message
    assert "\n" not in message, message
    with pytest.raises(ValueError, match=field.replace(".", r"\.")):
        opalray.Scene.preset("paper").replace(changes)


def test_dict_errors_match_the_scene_files(tmp_path):
    # The same message as a scene file's, less the file's name and line.
    path = tmp_path / "bad.toml"
    path.write_text("[render]\nwidth = 0\n")
    with pytest.raises(ValueError) as from_file:
        opalray.Scene.from_toml(path)
    with pytest.raises(ValueError) as from_dict:
        opalray.Scene({"render": {"width": 0}})
    assert str(from_file.value) == str(from_dict.value)
    path.write_text("[structure]\nvoid_ratoi = 0.3\n")
    with pytest.raises(ValueError) as from_file:
        opalray.Scene.from_toml(path)
    with pytest.raises(ValueError) as from_dict:
        opalray.Scene({"structure": {"void_ratoi": 0.3}})
    tail = str(from_dict.value).split("field `structure.void_ratoi`: ", 1)[1]
    assert str(from_file.value).endswith(tail), (from_file.value, from_dict.value)


def test_malformed_toml_and_unknown_preset():
    with pytest.raises(ValueError, match="line 1"):
        opalray.Scene.from_toml_str("[structure\n", "s.toml")
    with pytest.raises(ValueError, match="nonesuch") as err:
        opalray.Scene.preset("nonesuch")
    # A Python argument, not the command's flag.
    assert "--preset" not in str(err.value), err.value
    assert "Scene.preset(name)" in str(err.value), err.value
    with pytest.raises(ValueError, match="dict"):
        opalray.Scene([1, 2])  # type: ignore[arg-type]


def test_none_leaves_a_field_at_its_default_and_a_path_is_a_scene(tmp_path):
    base = opalray.Scene.preset("paper")
    wide = base.replace(render={"width": 100})
    assert wide.replace(render={"width": None}) == base
    assert opalray.Scene({"render": {"width": None}}) == base
    wide.save(tmp_path / "wide.toml")
    assert opalray.prepare(tmp_path / "wide.toml").scene == wide
    assert opalray.prepare(str(tmp_path / "wide.toml"), render={"height": 50}).scene == wide.replace(
        render={"height": 50})


def test_a_new_method_keeps_only_the_integrator_fields_it_takes():
    # A dict is refused another method's field, as a scene file is.
    with pytest.raises(ValueError, match=r"integrator\.max_depth") as err:
        opalray.Scene({"integrator": {"method": "lobe", "max_depth": 3}})
    assert '"path"' in str(err.value) and "\n" not in str(err.value)
    # Switching the method keeps the fields the new one takes and drops the others.
    path = opalray.Scene({"integrator": {"method": "path", "max_depth": 3, "spp": 5}})
    lobe = path.replace(integrator={"method": "lobe"})
    assert lobe["integrator"] == {"method": "lobe", "spp": 5, "seed": 0}
    stored = lobe.replace({"integrator.method": "stored", "integrator.cell_mm": 0.3})
    assert stored["integrator"] == {"method": "stored", "spp": 5, "seed": 0, "cell_mm": 0.3}
