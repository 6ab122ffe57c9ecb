"""The fast renderer (the default method): one framebuffer a sweep over the periodic tile (:mod:`.periodic`), its
OpenGL passes (:mod:`.passes`), the lattices and sampling settings (:mod:`.sampling`), the exact shares of a
period's regions (:mod:`.shares`) and the random tiles' regions counted on the GL side (:mod:`.counting`)."""
