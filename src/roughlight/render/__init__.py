"""Rendering: the OpenGL lighting equation, the detector's views, OSMesa and GL, and the methods that measure a
view (fast, naive, exact reference, implicit) with their sampling and exact shares. Imports only ``surfaces``."""
