"""The fast renderer (the default method): one framebuffer a sweep over the periodic tile (:mod:`.periodic`), its
OpenGL passes (:mod:`.passes`), the lattices and sampling settings (:mod:`.sampling`), the exact shares of a
period's regions (:mod:`.shares`) and the random tiles' regions counted on the CPU (:mod:`.counting`, :mod:`.raster`)."""

from .. import public_face

#: The room's face: what the rest of the package takes from it, by the module that holds it (imported on first use).
FACE = {"fast_sweep": "periodic", "FastSettings": "settings", "TileSettings": "settings"}
__getattr__, __all__ = public_face(__name__, FACE)
