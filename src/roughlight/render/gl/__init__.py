"""OpenGL for every GL method: the offscreen context and shader programs and their loader (:mod:`.context`), on
one of two headless platforms: OSMesa (:mod:`.osmesa`, the check that libOSMesa is there) or EGL (:mod:`.egl`,
its device route, for GPU nodes)."""
