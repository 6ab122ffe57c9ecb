"""Measurements of the methods themselves: speed against accuracy, the renderer against the exact reference at
every view, where methods fail (stability), the implicit surface and the random tiles. Imports ``analysis`` and
the stages below it."""
