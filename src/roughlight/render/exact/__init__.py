"""The exact reference: polygon clipping of a period's facets against each other and against the light
(:mod:`.clipping`), and every view's value from the exact visible, lit areas (:mod:`.reference`). No OpenGL."""
