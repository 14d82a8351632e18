"""opalray: a spectral renderer for the play of colour of precious opal, from Python.

    import opalray
    scene = opalray.Scene.preset("paper").replace(render={"width": 320, "height": 240})
    image = opalray.render(scene, light={"angle_deg": -45})
    image.rgb.shape          # (240, 320, 3), float32, linear
    image.save("flash.png")  # the bytes `opalray render` writes

The API is documented in docs/python.md.
"""

from ._opalray import __version__
from ._light import StoredLight
from ._render import Image, Optics, Stages, Structure, light_pass, prepare, render
from ._scene import Scene
from ._stone import Stone
from ._sweep import Sweep, map, sweep, sweep_angles

__all__ = [
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
    "render",
    "sweep",
    "sweep_angles",
]
