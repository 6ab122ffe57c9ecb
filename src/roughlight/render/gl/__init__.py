"""OpenGL for every GL method: the offscreen context and shader programs and their loader (:mod:`.context`), on
one of two headless platforms: OSMesa (:mod:`.osmesa`, the check that libOSMesa is there) or EGL (:mod:`.egl`,
its device route, for GPU nodes)."""

from .. import public_face

#: The room's face: what the rest of the package takes from it, by the module that holds it (imported on first use).
FACE = {"offscreen_renderer": "context", "release_contexts": "context", "describe": "context", "renderer": "context"}
__getattr__, __all__ = public_face(__name__, FACE)
