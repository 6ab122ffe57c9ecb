"""OpenGL for every GL method: the offscreen context (OSMesa), shader programs and their loader
(:mod:`.context`), and the check that libOSMesa is there (:mod:`.osmesa`)."""
