"""The registry of methods: every way of measuring a sweep, by the name ``render.method`` gives it.

Each :class:`Method` names its sweep function (``sweep(surface, incidence, azimuth, elevation, lighting,
settings)``, run through the one contract of :mod:`roughlight.render.sweep`) and its settings type, a frozen
dataclass that checks itself and says how it sampled the surface (``recorded``). Both are named by dotted path and
imported on first use, so a job imports only what its method needs: the exact reference loads no OpenGL.

- ``fast``: :func:`roughlight.render.fast.periodic.fast_sweep`, :class:`roughlight.render.fast.settings.FastSettings`;
- ``naive``: :func:`roughlight.render.naive.procedure.naive_sweep`,
  :class:`roughlight.render.naive.settings.NaiveSettings`;
- ``reference``: :func:`roughlight.render.exact.reference.reference_sweep`,
  :class:`roughlight.render.exact.settings.ReferenceSettings`;
- ``implicit_exact`` and ``implicit_correction``: :func:`roughlight.render.implicit.shader.implicit_sweep`,
  :class:`roughlight.render.implicit.settings.ImplicitSettings` with ``model`` ``exact`` or ``correction``;
- ``implicit_table``: the same with ``model`` ``table``: the facet shares read from a table of them
  (:mod:`roughlight.render.implicit.table`; its settings' ``table``: a share table or the file rule ``export``
  writes);
- ``implicit_clipped``: :func:`roughlight.render.implicit.shader.clipped_sweep`, the same settings with ``model``
  ``clipped``: the clipped scene, each view's facet shares clipped exactly in C
  (:mod:`roughlight.render.exact.pyramid`) and drawn on one quad (a regular surface only);
- ``mitsuba``: :func:`roughlight.render.mitsuba.scene.mitsuba_sweep`,
  :class:`roughlight.render.mitsuba.settings.MitsubaSettings` (Mitsuba 3, no OpenGL; what it draws on is
  :func:`roughlight.render.mitsuba.runtime.identity`'s).
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass

from . import shading

__all__ = ["Method", "METHODS", "NAMES", "NO_OPENGL", "method", "settings", "sweep", "recorded", "renderer_identity"]

#: What the exact reference runs on, as a sweep records it.
NO_OPENGL = "exact (no OpenGL)"


def _load(path: str):
    module, name = path.split(":")
    return getattr(importlib.import_module(module), name)


@dataclass(frozen=True)
class Method:
    """One method of measuring a sweep.

    Attributes
    ----------
    name : str
        The method's name (``render.method``).
    sweeper : str
        ``"module:function"`` of its sweep function.
    settings_type : str
        ``"module:class"`` of its settings.
    fixed : tuple of (str, value)
        Settings the name fixes (the implicit methods' ``model``).
    opengl : bool
        Whether it renders through OpenGL (all but the exact reference and Mitsuba).
    light_azimuth : bool
        Whether it lights from any azimuth (its sweep takes ``light_azimuth``); the others light from azimuth 0
        only and refuse any other.
    identity : str
        ``"module:function"`` saying what a method that is not OpenGL draws on: ``function(settings=None)``, with
        the sweep's settings or, without, of the machine; empty: :data:`NO_OPENGL` (the exact reference).
    """

    name: str
    sweeper: str
    settings_type: str
    fixed: tuple = ()
    opengl: bool = True
    identity: str = ""
    light_azimuth: bool = False

    def settings(self, knobs: dict | None = None):
        """The method's settings from ``knobs`` (the config's keys for it; None or {}: its defaults), checked."""
        kind = _load(self.settings_type)
        knobs = {**dict(self.fixed), **(knobs or {})}
        return self.checked(kind.from_config(knobs) if hasattr(kind, "from_config") else kind(**knobs))

    def checked(self, settings=None):
        """``settings`` (a dict of knobs or None: :meth:`settings`), refused unless they are this method's type
        and keep the values its name fixes."""
        if settings is None or isinstance(settings, dict):
            return self.settings(settings)
        kind = _load(self.settings_type)
        if not isinstance(settings, kind):
            raise TypeError(f"method {self.name!r} takes {kind.__name__}, got {type(settings).__name__}")
        for key, value in self.fixed:
            if getattr(settings, key) != value:
                raise ValueError(f"method {self.name!r} has {key}={value!r}, got {key}={getattr(settings, key)!r}")
        return settings

    def sweep(self, surface, incidence, azimuth, elevation, lighting=None, settings=None, light_azimuth=0.0) -> dict:
        """Measure a sweep (:func:`sweep`), with what it ran on (``renderer``)."""
        settings = self.checked(settings)
        light = {}
        if shading.check_light_azimuth(light_azimuth) != 0:
            if not self.light_azimuth:
                lit = ", ".join(m.name for m in METHODS.values() if m.light_azimuth)
                raise ValueError(f"method {self.name!r} lights from azimuth 0 only, got light_azimuth "
                                 f"{light_azimuth!r}: a light from another azimuth is measured by {lit}")
            light = {"light_azimuth": float(light_azimuth)}
        out = _load(self.sweeper)(surface, incidence, azimuth, elevation, lighting, settings, **light)
        if "renderer" not in out:  # a sweep that drew on nothing of the method's says what it counted on
            out["renderer"] = self.drawn_on(settings, made=True)
        return out

    def drawn_on(self, settings=None, made: bool = False) -> str:
        """What the method draws on: the GL renderer (``made``: the context a sweep made; else
        :func:`roughlight.render.gl.context.describe`), its :attr:`identity` (with ``settings``), or
        :data:`NO_OPENGL`."""
        if self.opengl:
            return _load("roughlight.render.gl.context:" + ("renderer" if made else "describe"))()
        return _load(self.identity)(settings) if self.identity else NO_OPENGL

    def recorded(self, settings=None, surface=None) -> dict:
        """How the method sampled ``surface`` (:func:`recorded`)."""
        return self.checked(settings).recorded(surface)


#: The methods, by name.
METHODS = {
    m.name: m
    for m in (
        Method("fast", "roughlight.render.fast.periodic:fast_sweep", "roughlight.render.fast.settings:FastSettings",
               light_azimuth=True),
        Method("naive", "roughlight.render.naive.procedure:naive_sweep",
               "roughlight.render.naive.settings:NaiveSettings"),
        Method("reference", "roughlight.render.exact.reference:reference_sweep",
               "roughlight.render.exact.settings:ReferenceSettings", opengl=False, light_azimuth=True),
        Method("implicit_exact", "roughlight.render.implicit.shader:implicit_sweep",
               "roughlight.render.implicit.settings:ImplicitSettings", (("model", "exact"),), light_azimuth=True),
        Method("implicit_correction", "roughlight.render.implicit.shader:implicit_sweep",
               "roughlight.render.implicit.settings:ImplicitSettings", (("model", "correction"),), light_azimuth=True),
        Method("implicit_table", "roughlight.render.implicit.shader:implicit_sweep",
               "roughlight.render.implicit.settings:ImplicitSettings", (("model", "table"),), light_azimuth=True),
        Method("implicit_clipped", "roughlight.render.implicit.shader:clipped_sweep",
               "roughlight.render.implicit.settings:ImplicitSettings", (("model", "clipped"),), light_azimuth=True),
        Method("mitsuba", "roughlight.render.mitsuba.scene:mitsuba_sweep",
               "roughlight.render.mitsuba.settings:MitsubaSettings", opengl=False,
               identity="roughlight.render.mitsuba.runtime:identity", light_azimuth=True),
    )
}

#: The methods' names, selectable with ``render.method``.
NAMES = tuple(METHODS)


def method(name: str) -> Method:
    """The method called ``name``; ``ValueError`` naming the choices for any other."""
    if name not in METHODS:
        raise ValueError(f"render.method must be one of {NAMES}, got {name!r}")
    return METHODS[name]


def settings(name: str, knobs=None):
    """The named method's settings: from its config keys ``knobs`` (a dict; None or {}: its defaults,
    :meth:`Method.settings`), or ``knobs`` itself when it is already the method's settings, checked
    (:meth:`Method.checked`). How code outside render/ makes a method's settings."""
    return method(name).checked(knobs)


def sweep(name: str, surface, incidence, azimuth, elevation, lighting=None, settings=None, light_azimuth=0.0) -> dict:
    """Measure a sweep with the named method.

    Parameters
    ----------
    name : str
        One of :data:`NAMES`.
    surface : Surface or RandomSurface
    incidence : float
        Light elevation above the surface plane, degrees in [0, 90].
    azimuth, elevation : (n_views,) arrays
        Views, degrees (:func:`roughlight.render.sweep.sweep_views`).
    lighting : Lighting, optional
    settings : the method's settings type, a dict of its knobs, or None (its defaults)
    light_azimuth : float, optional
        The light's azimuth, degrees (0: the study's light, ``L = (cos i, 0, sin i)``); a method that lights from
        azimuth 0 only (:attr:`Method.light_azimuth` False) refuses any other with ``ValueError``.

    Returns
    -------
    dict
        ``diffuse``, ``specular``, ``total`` and ``coverage``: (n_views,) arrays (0-255; coverage 0-1);
        ``seconds``: wall time of the sweep (:data:`roughlight.render.sweep.RESULT`); ``renderer``: what it ran on
        (:func:`roughlight.render.gl.context.renderer`: the GL renderer, its OpenGL version and the platform;
        :data:`NO_OPENGL` for the exact reference; Mitsuba's version and variant for ``mitsuba``).
    """
    return method(name).sweep(surface, incidence, azimuth, elevation, lighting, settings, light_azimuth)


def recorded(name: str, settings=None, surface=None) -> dict:
    """How the named method sampled ``surface``, as the study table and the benchmark record it.

    Returns
    -------
    dict: ``pixels_per_period`` (int; a random tile's per cell), ``sampling`` (``lattice``, ``grid`` or
    ``adaptive`` for fast, ``window`` for naive, ``exact`` for the reference, ``fibonacci`` for the implicit
    shader (``table`` for its table model, ``clipped`` for the clipped scene), ``mitsuba <variant>, <n> spp,
    <bounces>`` for Mitsuba) and ``shadow_map_size`` (texels a side; 0 where there is none).
    """
    return method(name).recorded(settings, surface)


def renderer_identity(name: str) -> str:
    """What this process draws a sweep of the method ``name`` on: the GL renderer, its OpenGL version (with the
    driver's) and the platform (:func:`roughlight.render.gl.context.describe`, which makes a context for the
    purpose when none was made yet); :data:`NO_OPENGL` for the exact reference; for ``mitsuba`` the machine's
    Mitsuba, Dr.Jit and LLVM (:func:`roughlight.render.mitsuba.runtime.identity`; the variant is a setting)."""
    return method(name).drawn_on()
