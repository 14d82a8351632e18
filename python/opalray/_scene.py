"""The scene: a plain dict with the schema of the TOML scene files (docs/scene-format.md).

Every dict goes through the core's own serde structs and ``validate()``, so defaults, unknown
fields, wrong types and out-of-range values behave exactly as in a scene file; errors are a
``ValueError`` with the core's one-line message naming the field path.
"""

from __future__ import annotations

import copy
import os
from collections.abc import Mapping
from typing import Any

from . import _opalray
from ._notebook import scene_summary

__all__ = ["Scene", "as_scene"]


def _merge(base: dict, changes: Mapping, path: str = "") -> None:
    """Merge ``changes`` into ``base`` in place: dicts merge key by key, anything else replaces."""
    for key, value in changes.items():
        if not isinstance(key, str):
            raise ValueError(f"scene dict: field `{path}{key!r}`: keys must be strings")
        if "." in key:
            # A dotted path: `crystal.sphere_diameter_nm`.
            head, rest = key.split(".", 1)
            _merge(base, {head: {rest: value}}, path)
            continue
        if isinstance(value, Mapping) and isinstance(base.get(key), dict):
            _merge(base[key], value, f"{path}{key}.")
        else:
            base[key] = copy.deepcopy(dict(value) if isinstance(value, Mapping) else value)


class Scene:
    """A complete, validated scene.

    ``Scene()`` is the preset ``opalray render`` renders (:data:`opalray.DEFAULT_PRESET`,
    ``black-opal``); ``Scene(d)`` reads a (partial) dict as a scene file is read, missing
    fields taking their defaults (those of the ``paper`` preset). A Scene is immutable:
    ``replace`` returns a new one.
    """

    __slots__ = ("_data",)

    def __init__(self, data: Mapping | Scene | None = None):
        if data is None:
            data = _opalray.preset(_opalray.DEFAULT_PRESET)
        elif isinstance(data, Scene):
            data = data._data
        elif isinstance(data, Mapping):
            data = dict(data)
        self._data = _opalray.normalize(data)

    @classmethod
    def preset(cls, name: str | None = None) -> Scene:
        """A named preset (:func:`opalray.presets` lists them; ``paper``: the paper's fig. 10
        set-up, 640 × 480, light at 30°); without a name the one ``opalray render`` renders,
        :data:`opalray.DEFAULT_PRESET`."""
        return cls._of(_opalray.preset(_opalray.DEFAULT_PRESET if name is None else name))

    @classmethod
    def from_toml(cls, path: str | os.PathLike) -> Scene:
        """Read a TOML scene file; errors name the file, the field and the line. A relative
        ``environment.path`` is taken from the file's folder."""
        path = os.fspath(path)
        try:
            with open(path, encoding="utf-8") as f:
                text = f.read()
        except OSError as e:
            raise OSError(f"{path}: {e.strerror}") from e
        complete = _opalray.parse_toml(text, path)
        # A map named in the file lies beside it (as for `opalray render scene.toml`).
        environment = complete["environment"]
        if environment["path"] and not os.path.isabs(environment["path"]):
            environment["path"] = os.path.join(os.path.dirname(path), environment["path"])
        return cls._of(complete)

    @classmethod
    def from_image(cls, path: str | os.PathLike) -> Scene:
        """The scene a PNG or EXR image written by opalray (``Image.save``, ``opalray
        render``) records in its header: rendering it again gives the same image."""
        return cls._of(_opalray.read_scene(os.fspath(path)))

    @classmethod
    def from_toml_str(cls, text: str, origin: str = "scene text") -> Scene:
        """Parse TOML text; ``origin`` names it in errors."""
        return cls._of(_opalray.parse_toml(text, origin))

    @classmethod
    def _of(cls, complete: dict) -> Scene:
        scene = cls.__new__(cls)
        scene._data = complete
        return scene

    def to_dict(self) -> dict:
        """The complete scene as a new dict of dicts, every field filled in."""
        return copy.deepcopy(self._data)

    def to_toml(self) -> str:
        """The complete scene as TOML text (as ``opalray scene`` prints it)."""
        return _opalray.to_toml_text(self._data)

    def save(self, path: str | os.PathLike) -> None:
        """Write the scene as a TOML file."""
        with open(path, "w", encoding="utf-8") as f:
            f.write(self.to_toml())

    def replace(self, changes: Mapping | None = None, /, **more: Any) -> Scene:
        """A copy with ``changes`` applied, validated.

        Each keyword is a section whose dict is merged into that section
        (``replace(crystal={"sphere_diameter_nm": 215})`` keeps the crystal's other fields),
        or a dotted field path, given as a dict key or through ``**``
        (``replace({"light.angle_deg": -45})``). Nested dicts merge; lists and values replace.
        A new ``integrator.method`` keeps the integrator's fields the new method takes and
        drops the others (``replace(integrator={"method": "lobe"})`` on a path-traced scene).
        """
        data = self.to_dict()
        merged = copy.deepcopy(data)
        if changes:
            _merge(merged, changes)
        _merge(merged, more)
        section = merged.get("integrator")
        method = section.get("method") if isinstance(section, dict) else None
        keep = _opalray.integrator_fields(method) if isinstance(method, str) else None
        if keep is not None and method != data["integrator"]["method"]:
            # A switch of method keeps the fields the new one takes and drops the others;
            # the fields given with it are kept, and checked.
            old = data["integrator"]
            data["integrator"] = {k: v for k, v in old.items() if k == "method" or k in keep}
            if changes:
                _merge(data, changes)
            _merge(data, more)
            merged = data
        return Scene(merged)

    def __getitem__(self, section: str) -> Any:
        return copy.deepcopy(self._data[section])

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Scene) and self._data == other._data

    def __hash__(self) -> int:
        return hash(self.to_toml())

    def __reduce__(self):
        return (Scene, (self._data,))

    def __repr__(self) -> str:
        # The fields its method reads (the cell grid of the two passes, the stone model of
        # the others); ``to_toml()`` has them all.
        return f"Scene({', '.join(scene_summary(self._data))})"


def as_scene(scene: Scene | Mapping | str | os.PathLike | None, **overrides: Any) -> Scene:
    """A Scene from a Scene, a dict, a TOML file's path or None (the default preset of
    ``opalray render`` and every command, :data:`opalray.DEFAULT_PRESET`), with ``overrides``
    applied as by :meth:`Scene.replace`."""
    if scene is None:
        scene = Scene.preset(_opalray.DEFAULT_PRESET)
    elif isinstance(scene, (str, os.PathLike)):
        scene = Scene.from_toml(scene)
    elif not isinstance(scene, Scene):
        scene = Scene(scene)
    return scene.replace(**overrides) if overrides else scene
