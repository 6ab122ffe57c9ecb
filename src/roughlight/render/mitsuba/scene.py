"""A sweep in Mitsuba 3: the periodic field as one mesh, the study's light and material, one render a view.

The scene is built once a sweep (:class:`FieldScene`; once a group of azimuths when one field for every view
would be too big, :func:`roughlight.render.mitsuba.field.view_groups`): the field of periods its views need
(:mod:`.field`) as one triangle mesh with flat facets (no vertex normals: Mitsuba shades with each triangle's own
normal), the study's material (:func:`roughlight.render.mitsuba.bsdf.material`) and a ``directional`` emitter
toward ``-L`` of irradiance ``pi``, so that a lit facet's diffuse is ``m_d N.L`` a unit ``J``. Each view is one
render through its own orthographic detector (:func:`roughlight.render.mitsuba.field.sensor_matrix`), ``rgba``
film with a box filter (a pixel is the mean of its own samples). On the study's 0-255 scale each pixel of a
component is then ``J`` times its channel, plus the ambient term ``J m_a A`` on the diffuse and the total, clamped
and rounded to its 8-bit value (:func:`roughlight.render.shading.quantize`, ties within :data:`TIE_SLACK`), and the
view's value is the mean over the film, as the framebuffer's.

Conventions shared with the reference (render/exact/reference.py):

- the light in the plane (incidence 0, ``L_z < 1e-9``) on a surface that is not the plate lights nothing
  (ambient only); the plate's ``N.L`` is 0 there anyway;
- the plate casts no shadow, so ``lighting.shadows`` off is accepted there; on a rough surface Mitsuba always
  casts them, and the method refuses ``shadows`` off and ``specular_shadows`` off (the thesis's unshadowed
  specular is no light transport) rather than measure something else.
"""

from __future__ import annotations

import numpy as np

from .. import sweep
from ..shading import Lighting, light_direction, quantize
from . import runtime
from .bsdf import material, register
from .field import field_triangles, sensor_matrix, surface_height, tile_triangles, view_groups
from .settings import MitsubaSettings

__all__ = ["TIE_SLACK", "refusal", "FieldScene", "mitsuba_sweep"]

#: Values within this of a half step round up, as :func:`roughlight.render.shading.quantize` rounds ties up.
#: Mitsuba computes in single precision: a plate's diffuse ``127 sin 30 = 63.5`` comes out as 63.4999962 (4e-6
#: low), and the specular lobe's power amplifies the error of its base ``zeta`` times: at the plate's mirror view
#: the total ``63.5 + 127`` came out up to 1e-3 of a level low on some pixels (rounded to 190, not 191).
TIE_SLACK = 2e-3
#: The light counts as in the plane below this ``L_z`` (the reference's and the fast renderer's threshold).
GRAZING_LIGHT = 1e-9
#: How much of a window's samples may miss the surface. Embree (Mitsuba's ray tracer on the CPU, in its fast mode)
#: lets about one ray in 10^5 slip through the shared edge of two facets (seen: 1 sample of 65,536 at e 110,
#: phi 150 on t 0.5, a 1); a pixel's value is the mean of its samples that met the surface (:meth:`FieldScene.render`).
#: A field too small for a view would leave whole rows of pixels empty, far more than this.
COVERAGE_TOLERANCE = 1e-3


def refusal(surface, lighting: Lighting, settings: MitsubaSettings) -> str | None:
    """Why the method cannot measure this sweep as the study defines it, or None."""
    if surface.is_plate:
        return None
    if not lighting.shadows:
        return ("render.shadows: false is not available with the mitsuba method (Mitsuba's light always casts "
                "shadows); use render.method fast or reference")
    if not lighting.specular_shadows and material(lighting, settings)["specular"] == "measured":
        return ("render.specular_shadows: false is not available with the mitsuba method (the thesis's unshadowed "
                "specular is no light transport); set render.mitsuba.specular false to measure the diffuse alone, "
                "or use render.method fast or reference")
    return None


def is_lit(surface, incidence) -> bool:
    """Whether any light reaches the surface: not when it lies in the plane of a surface that is not the plate."""
    return bool(surface.is_plate or light_direction(incidence)[2] >= GRAZING_LIGHT)


class FieldScene:
    """A Mitsuba scene of a sweep's views: the field of ``cells`` (:func:`roughlight.render.mitsuba.field.view_groups`),
    the light and the material; :meth:`view` renders one view."""

    def __init__(self, surface, incidence: float, cells, lighting: Lighting, settings: MitsubaSettings,
                 light_azimuth: float = 0.0, lowest: float | None = None):
        self.mi, self.variant = runtime.load(settings.variant)
        #: the smallest ``V_z`` of the views to render (None: the first view's), which sets the detector's far clip
        self.lowest = lowest
        self._camera = None  # (sensor, its parameters, its far clip): one detector moved from view to view
        self.settings, self.lighting = settings, lighting
        self.material = material(lighting, settings)
        self.height = surface_height(surface)
        self.resolution = settings.resolution(surface)
        light = light_direction(incidence, light_azimuth)
        self.lit = is_lit(surface, incidence)
        self.triangles = field_triangles(tile_triangles(surface), cells)
        self.scene = self.mi.load_dict({
            "type": "scene",
            "integrator": settings.integrator(),
            "light": {"type": "directional", "direction": (-light).tolist(),
                      "irradiance": {"type": "rgb", "value": float(np.pi) if self.lit else 0.0}},
            "field": self._mesh(),
        })

    def _mesh(self):
        mi = self.mi
        if self.material["specular"] == "measured":
            register(mi)
        props = mi.Properties()
        props["bsdf"] = mi.load_dict(self.material["bsdf"])
        vertices = self.triangles.reshape(-1, 3)
        mesh = mi.Mesh("field", len(vertices), len(self.triangles), props=props)
        params = mi.traverse(mesh)
        params["vertex_positions"] = type(params["vertex_positions"])(vertices.ravel())
        params["faces"] = type(params["faces"])(np.arange(len(vertices), dtype=np.uint32))
        params.update()
        return mesh

    def _sensor(self, view_dir):
        """The detector of the view ``view_dir``: one sensor, built at the first view with the far clip the lowest
        view needs (:attr:`lowest`) and moved to each view through its parameters. A sensor built for each view
        baked its transform into the kernel: Dr.Jit compiled one a view (0.2 s each, with a cold cache), where
        the moved sensor's transform is an argument of one kernel; the films are the same to the bit."""
        matrix, far = sensor_matrix(view_dir, self.settings.periods, self.height)
        if self.lowest is not None:
            far = max(far, sensor_matrix((0.0, 0.0, float(self.lowest)), self.settings.periods, self.height)[1])
        if self._camera is None or far > self._camera[2]:
            sensor = self.new_sensor(matrix, far)
            self._camera = (sensor, self.mi.traverse(sensor), far)
        sensor, params, _ = self._camera
        params["to_world"] = self.mi.Transform4f(matrix)
        params.update()
        return sensor

    @property
    def detector(self):
        """The sensor moved from view to view (None before the first view)."""
        return None if self._camera is None else self._camera[0]

    def new_sensor(self, matrix, far: float):
        """An orthographic detector at ``matrix`` (:func:`roughlight.render.mitsuba.field.sensor_matrix`) with the
        far clip ``far``, the film and sampler of the settings."""
        side = self.resolution
        return self.mi.load_dict({
            "type": "orthographic", "to_world": self.mi.ScalarTransform4f(matrix), "near_clip": 1e-3,
            "far_clip": far,
            "film": {"type": "hdrfilm", "width": side, "height": side, "rfilter": {"type": "box"},
                     "pixel_format": "rgba", "component_format": "float32"},
            "sampler": {"type": "independent", "sample_count": self.settings.samples_per_pixel},
        })

    def render(self, view_dir, seed: int = 0) -> np.ndarray:
        """The view's film, ``(side, side, 4)`` float64: red, green, blue as :mod:`.bsdf` defines them, a unit
        ``J``, each the mean of the pixel's samples that met the surface (a sample that slipped through a crack
        between two facets is left out: :data:`COVERAGE_TOLERANCE`); alpha, the share of them that did."""
        return self.film(self.mi.render(self.scene, sensor=self._sensor(view_dir), seed=int(seed)))

    def film(self, image) -> np.ndarray:
        """:meth:`render`'s film of Mitsuba's ``image`` (the colours over the share of samples that met the
        surface)."""
        film = np.asarray(image, dtype=np.float64).reshape(self.resolution, self.resolution, 4)
        alpha = film[..., 3:]
        film[..., :3] = np.where(alpha > 0, film[..., :3] / np.where(alpha > 0, alpha, 1.0), 0.0)
        return film

    def view(self, view_dir, seed: int = 0) -> dict:
        """The view's ``diffuse``, ``specular``, ``total`` (mean 8-bit value, 0-255; NaN where not measured), each one's
        ``{component}_unrounded`` (the mean of the film's values clamped to [0, 255], not rounded) and
        ``coverage``."""
        film = self.render(view_dir, seed)
        j = float(self.lighting.light)
        ambient = j * float(self.lighting.ambient_reflectance) * float(self.lighting.ambient)
        pixels = {"diffuse": j * self.material["diffuse_scale"] * film[..., 0] + ambient}
        kind = self.material["specular"]
        if kind == "measured":
            pixels.update(specular=j * film[..., 1], total=j * film[..., 2] + ambient)
        out = {}
        for name in ("diffuse", "specular", "total"):
            if name in pixels:
                out[name] = quantize(pixels[name], TIE_SLACK).mean()
                out[f"{name}_unrounded"] = np.clip(pixels[name], 0.0, 255.0).mean()  # the float film's, clamped
            elif kind == "zero":  # no specular: the total is the diffuse
                out[name], out[f"{name}_unrounded"] = (0.0, 0.0) if name == "specular" else (
                    out["diffuse"], out["diffuse_unrounded"])
            else:
                out[name] = out[f"{name}_unrounded"] = float("nan")
        return {**out, "coverage": float(film[..., 3].mean())}


def mitsuba_sweep(surface, incidence, azimuth, elevation, lighting=None, settings=None, light_azimuth=0.0) -> dict:
    """Mean 8-bit value of each component for many views of one surface, rendered by Mitsuba 3.

    Parameters
    ----------
    surface : Surface or RandomSurface (the plate included)
    incidence : float, light elevation above the plane, degrees in [0, 90]
    light_azimuth : float, the light's azimuth, degrees (0, the study's)
    azimuth, elevation : array_like, degrees (:func:`roughlight.render.sweep.sweep_views`)
    lighting : Lighting, optional
    settings : MitsubaSettings, optional

    Returns
    -------
    dict as every method's (:data:`roughlight.render.sweep.RESULT`): ``diffuse``, ``specular``, ``total``
    (NaN where the settings do not measure them: :func:`roughlight.render.mitsuba.bsdf.material`), their
    ``_unrounded`` means (the float film's; NaN where they are), ``_unshadowed`` NaN (Mitsuba always casts the
    shadows), ``coverage`` (1 at every measured view; RuntimeError if a view's window sees past the field) and
    ``seconds``; grazing views are 0.
    """
    lighting = Lighting() if lighting is None else lighting
    settings = MitsubaSettings() if settings is None else settings
    problem = refusal(surface, lighting, settings)
    if problem:
        raise ValueError(problem)

    def step(out, views, incidence, lighting):
        directions = views.directions()
        groups = view_groups(len(tile_triangles(surface)), surface_height(surface),
                             light_direction(incidence, light_azimuth),
                             directions, settings.periods, is_lit(surface, incidence))
        for rows, cells in groups:
            field = FieldScene(surface, incidence, cells, lighting, settings, light_azimuth,
                               lowest=float(directions[rows, 2].min()))
            for row in rows:
                k = views.measured[row]
                values = field.view(directions[row], seed=int(k))
                if values["coverage"] < 1.0 - COVERAGE_TOLERANCE:
                    raise RuntimeError(f"mitsuba: the view (e={views.elevation[k]}, phi={views.azimuth[k]}) saw past "
                                       f"the field (coverage {values['coverage']}): a bug of the field's extent")
                for name, value in values.items():
                    out[name][k] = value
            del field

    # the film is float: the means before rounding; inner shadows cannot be switched off (Mitsuba's light always
    # casts them, refusal), so no mean without them (NaN)
    return sweep.measure(step, incidence, azimuth, elevation, lighting, gives=("unrounded",))
