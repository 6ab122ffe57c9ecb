"""The naive method, the thesis's own procedure: pyrender draws a finite patch once a view and a capture window
is averaged (:mod:`.procedure`)."""
