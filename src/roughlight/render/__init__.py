"""Rendering: the OpenGL lighting equation, the detector's views, OSMesa and GL, and the methods that measure a
view (fast, naive, exact reference, implicit, Mitsuba) with their sampling and exact shares. Imports only
``surfaces``."""

import importlib


def public_face(package: str, names: dict):
    """A room's ``__getattr__`` (PEP 562) and ``__all__``: the names ``names`` maps to its modules, each module
    imported on first use, so that the room's face loads nothing (no OpenGL) until a name is taken. Outside
    render/, a room is reached only through its face (render/README.md; tests/test_layers.py checks it)."""

    def __getattr__(name: str):
        if name not in names:
            raise AttributeError(f"module {package!r} has no attribute {name!r} (its face: {sorted(names)})")
        return getattr(importlib.import_module(f"{package}.{names[name]}"), name)

    return __getattr__, sorted(names)
