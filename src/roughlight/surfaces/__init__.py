"""Surfaces: the regular grid of truncated pyramids and the flat control, their facets and projected geometry,
and the random tiles (seeded periodic ensembles). Imports no other stage."""
