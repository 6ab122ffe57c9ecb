"""The exact reference: polygon clipping of a period's facets against each other and against the light
(:mod:`.clipping`, by GEOS; :mod:`.pyramid`, a regular surface's in C), and every view's value from the exact
visible, lit areas (:mod:`.reference`). No OpenGL."""

from .. import public_face

#: The room's face: what the rest of the package takes from it, by the module that holds it (imported on first use).
FACE = {"reference_sweep": "reference", "reference_views": "reference", "visible_lit_areas": "reference",
        "LitScene": "reference", "shares_under": "reference", "view_areas": "pyramid", "ReferenceSettings": "settings",
        "PyramidScene": "pyramid", "pyramid_shares": "pyramid"}
__getattr__, __all__ = public_face(__name__, FACE)
