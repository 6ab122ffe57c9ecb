"""The study's material as a Mitsuba BSDF: Mitsuba's own ``diffuse`` plus the study's Phong or Blinn-Phong
specular, on three channels.

Mitsuba 3 has no Phong lobe. The plugin :data:`PLUGIN` wraps a nested ``diffuse`` BSDF (Mitsuba's code gives the
diffuse) and adds the study's specular term (:mod:`roughlight.render.shading`), one component a colour channel:

- red: the diffuse alone, ``rho cos(theta_l) / pi``;
- green: the specular alone, ``m_s S / pi`` with ``S = max(R.V, 0)^zeta`` (Phong, ``R`` the light mirrored about
  the normal) or ``max(N.H, 0)^zeta`` (Blinn-Phong), zero unless both the light and the detector are above the
  facet (``N.L > 0``, ``N.V > 0``);
- blue: their sum, the total.

Under a ``directional`` emitter of irradiance ``pi`` a lit point's channels are then the study's ``m_d N.L``,
``m_s S`` and their sum, per unit ``J``. Mitsuba's BSDF value includes the cosine of the light's angle, which the
OpenGL equation has on the diffuse alone, so the specular lobe is not divided by it. When light bounces (``path``)
the plugin samples the cosine hemisphere of the nested diffuse and weighs each channel by its own value, so each
channel carries its own material's light: the red a purely diffuse surface's, the green the lobe's alone, the blue
the study's whole material's.

A Python plugin runs at every sample; in the LLVM and CUDA variants it is traced into the kernel (no cost to
speak of), in ``scalar_rgb`` it is about twenty times slower than the diffuse alone.
"""

from __future__ import annotations

__all__ = ["PLUGIN", "register", "material"]

#: The plugin's name in Mitsuba's registry.
PLUGIN = "roughlight_study"

#: The variants the plugin is registered in (once each).
_REGISTERED: set = set()


def _plugin_class(mi):
    """The BSDF class for ``mi``'s current variant (Mitsuba's Python base class depends on it)."""
    import drjit as dr

    class StudyBSDF(mi.BSDF):
        def __init__(self, props):
            mi.BSDF.__init__(self, props)
            self.diffuse = props["diffuse"]
            self.specular = float(props["specular_reflectance"])
            self.shininess = float(props["shininess"])
            self.blinn = bool(props["blinn"])
            flags = mi.BSDFFlags.DiffuseReflection | mi.BSDFFlags.FrontSide
            self.m_flags = flags
            self.m_components = [flags]

        def lobe(self, si, wo, active):
            """``m_s S / pi`` in the local frame (the normal is +z); 0 unless the light and the detector face it."""
            if self.blinn:
                base = mi.Frame3f.cos_theta(dr.normalize(wo + si.wi))
            else:
                base = dr.dot(mi.Vector3f(-wo.x, -wo.y, wo.z), si.wi)
            scale = self.specular * dr.inv_pi
            value = scale if self.shininess == 0 else scale * dr.power(dr.maximum(base, 0.0), self.shininess)
            facing = active & (mi.Frame3f.cos_theta(wo) > 0) & (mi.Frame3f.cos_theta(si.wi) > 0)
            return dr.select(facing, value, 0.0)

        def eval(self, ctx, si, wo, active=True):
            diffuse = self.diffuse.eval(ctx, si, wo, active)[0]
            specular = self.lobe(si, wo, active)
            return mi.Color3f(diffuse, specular, diffuse + specular)

        def pdf(self, ctx, si, wo, active=True):
            return self.diffuse.pdf(ctx, si, wo, active)

        def eval_pdf(self, ctx, si, wo, active=True):
            return self.eval(ctx, si, wo, active), self.pdf(ctx, si, wo, active)

        def sample(self, ctx, si, sample1, sample2, active=True):
            bs, _ = self.diffuse.sample(ctx, si, sample1, sample2, active)
            value = self.eval(ctx, si, bs.wo, active)
            return bs, dr.select(bs.pdf > 0, value / dr.maximum(bs.pdf, 1e-30), 0.0)

        def to_string(self):
            model = "blinn" if self.blinn else "phong"
            return f"StudyBSDF[specular={self.specular}, shininess={self.shininess}, {model}]"

    return StudyBSDF


def register(mi) -> str:
    """Register :data:`PLUGIN` in ``mi``'s current variant (once); its name."""
    variant = mi.variant()
    if variant not in _REGISTERED:
        kind = _plugin_class(mi)
        mi.register_bsdf(PLUGIN, lambda props: kind(props))
        _REGISTERED.add(variant)
    return PLUGIN


def material(lighting, settings) -> dict:
    """How the study's material is rendered: the BSDF's dictionary and what each channel is.

    Parameters
    ----------
    lighting : Lighting
    settings : MitsubaSettings

    Returns
    -------
    dict
        ``bsdf``: Mitsuba's dictionary (``diffuse``, or :data:`PLUGIN` wrapping one); ``albedo``: the diffuse
        reflectance ``rho`` light bounces with; ``diffuse_scale``: ``m_d / rho`` (0 when ``rho`` is 0), which keeps
        direct light on the study's scale; ``specular``: ``"measured"`` (the plugin's green and blue channels),
        ``"zero"`` (``m_s`` is 0: the specular is 0 and the total the diffuse) or ``"skipped"`` (NaN: the setting
        ``specular`` is off, or an ``albedo`` is set).
    """
    m_d = float(lighting.diffuse_reflectance)
    rho = float(settings.albedo) if settings.albedo is not None and m_d > 0 else m_d
    diffuse = {"type": "diffuse", "reflectance": {"type": "rgb", "value": rho}}
    if float(lighting.specular_reflectance) == 0.0 and settings.albedo is None:
        specular = "zero"
    elif settings.specular and settings.albedo is None:
        specular = "measured"
    else:
        specular = "skipped"
    bsdf = diffuse if specular != "measured" else {
        "type": PLUGIN, "diffuse": diffuse, "specular_reflectance": float(lighting.specular_reflectance),
        "shininess": float(lighting.shininess), "blinn": lighting.specular_model == "blinn"}
    return {"bsdf": bsdf, "albedo": rho, "diffuse_scale": m_d / rho if rho > 0 else 0.0, "specular": specular}
