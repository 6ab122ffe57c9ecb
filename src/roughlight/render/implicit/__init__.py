"""The implicit rough surface, the thesis's goal: the models in numpy (:mod:`.model`) and drawn as one flat quad
through one shader (:mod:`.shader`)."""
