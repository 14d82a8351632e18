"""opalray: a spectral renderer for the play of colour of precious opal, from Python.

    import opalray
    opalray.presets()        # ['black-opal', 'harlequin', …]; opalray.DEFAULT_PRESET first
    scene = opalray.Scene.preset("paper").replace(render={"width": 320, "height": 240})
    image = opalray.render(scene, light={"angle_deg": -45})
    image.rgb.shape          # (240, 320, 3), float32, linear
    image.save("flash.png")  # the bytes `opalray render` writes

The API is documented in docs/python.md.
"""

from ._opalray import DEFAULT_PRESET, PRESETS, __version__
from ._light import StoredLight
from ._render import Image, Optics, Stages, Structure, light_pass, prepare, render
from ._scene import Scene
from ._stone import Stone
from ._sweep import Sweep, map, sweep, sweep_angles



def presets() -> list[str]:
    """The names of the preset scenes (``Scene.preset(name)``, ``opalray render --preset
    NAME``); :data:`DEFAULT_PRESET`, the scene every command and :func:`render` start from
    when given none, among them."""
    return list(PRESETS)


__all__ = [
    "DEFAULT_PRESET",
    "Image",
    "Optics",
    "Scene",
    "Stages",
    "Stone",
    "StoredLight",
    "Structure",
    "Sweep",
    "__version__",
    "light_pass",
    "map",
    "prepare",
    "presets",
    "render",
    "sweep",
    "sweep_angles",
]
