"""The naive method, the thesis's own procedure: pyrender draws a finite patch once a view and a capture window
is averaged (:mod:`.procedure`)."""

from .. import public_face

#: The room's face: what the rest of the package takes from it, by the module that holds it (imported on first use).
FACE = {"naive_sweep": "procedure", "render_picture": "procedure", "CompiledShaders": "procedure",
        "NaiveScene": "procedure", "look_pose": "procedure", "up_vector": "procedure", "NaiveSettings": "settings"}
__getattr__, __all__ = public_face(__name__, FACE)
