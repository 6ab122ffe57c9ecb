"""The implicit rough surface, the thesis's goal: the models in numpy (:mod:`.model`) and drawn as one flat quad
through one shader (:mod:`.shader`); the clipped scene's shares, clipped exactly on the CPU (:mod:`.clipped`); the
table model's table of facet shares (:mod:`.table`), measured by the exact reference and kept (:mod:`.tabulate`)."""

from .. import public_face

#: The room's face: what the rest of the package takes from it, by the module that holds it (imported on first use).
FACE = {"implicit_sweep": "shader", "render_field": "shader", "clipped_sweep": "shader", "clipped_shares": "clipped",
        "clipped_state_bytes": "clipped", "ImplicitSettings": "settings", "ShareTable": "table",
        "save_table": "table", "load_table": "table", "table_shares": "table", "table_values": "table",
        "hot_spot_weight": "table", "HOT_SPOT_BLEND": "table",
        "CHANNELS": "table", "SCALE": "table", "TABLE": "tabulate", "incidence_nodes": "tabulate", "elevation_nodes": "tabulate",
        "channel_shares": "tabulate", "measure_table": "tabulate", "tabulate_surface": "tabulate", "cached_table": "tabulate"}
__getattr__, __all__ = public_face(__name__, FACE)
