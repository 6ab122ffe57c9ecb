"""Mitsuba 3 as a method: the periodic field rendered by a physically based renderer nobody here wrote, direct
light alone by default (a check of the exact reference), light that bounces on request (what the OpenGL equation
leaves out). The scene and the sweep (:mod:`.scene`), the field and the detector in numpy (:mod:`.field`), the
study's material as a BSDF (:mod:`.bsdf`), Mitsuba's and Dr.Jit's environment and variant (:mod:`.runtime`), the
settings (:mod:`.settings`); docs/mitsuba.md. A surface's BRDF as a file Mitsuba's own ``measured`` plugin loads, and a
flat quad rendered with it (:mod:`.measured`; docs/export-mitsuba.md), and whether light that bounces off it stays
unbiased (:mod:`.bounces`)."""

from .. import public_face

#: The room's face: what the rest of the package takes from it, by the module that holds it (imported on first use;
#: none of them imports Mitsuba until a sweep renders).
FACE = {"mitsuba_sweep": "scene", "MitsubaSettings": "settings", "VARIANTS": "settings", "identity": "runtime",
        "check_mitsuba": "runtime", "MitsubaUnavailable": "runtime", "variant_in_use": "runtime",
        "table_nodes": "measured", "half_vectors": "measured", "reflect": "measured", "tabulate": "measured",
        "warp_density": "warp", "node_half_vectors": "warp",
        "write_measured": "measured", "read_measured": "measured", "evaluate": "measured", "render_flat": "measured"}
__getattr__, __all__ = public_face(__name__, FACE)
