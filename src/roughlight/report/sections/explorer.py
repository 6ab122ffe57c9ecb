"""The page's hemisphere explorer: the data rule ``explorer_data`` wrote (:func:`roughlight.report.explorer.
explorer_data`) and the explorer's own script (``templates/explorer.js``), for ``templates/explorer.html``.

The data go into the page as two blocks that never run (``<script type="application/json">`` for the index,
``<script type="application/octet-stream">`` for the base64 sweeps); the script is the only code that runs, and
the page's Content-Security-Policy names it by its hash (:func:`roughlight.report.page_templates.
content_security_policy`).
"""

from __future__ import annotations

import json
from functools import cache

from ..page_templates import environment
from ..registry import Section

#: The kinds as the page names them.
KIND_NAMES = {"control": "the control plate", "pyramids": "regular pyramids", "random_pyramids": "random pyramids",
              "random_heightfield": "random heightfield"}


@cache
def explorer_script() -> str:
    """The explorer's JavaScript (``templates/explorer.js``), as the page holds it."""
    env = environment()
    text = env.loader.get_source(env, "explorer.js")[0]
    if "</script" in text.lower():
        raise ValueError("explorer.js must not contain '</script'")
    return text


def _index_json(data: dict) -> str:
    """The data's index (everything but the sweeps) as JSON that is safe inside a ``<script>`` block."""
    index = {k: v for k, v in data.items() if k != "data"}
    return json.dumps(index, separators=(",", ":")).replace("</", "<\\/")


def _held(data: dict) -> dict:
    """How many sweeps of each sort the page holds: control, regular, ensemble means, seeds."""
    sets = data["datasets"]
    return {"control": sum(d["kind"] == "control" for d in sets),
            "regular": sum(d["kind"] == "pyramids" for d in sets),
            "means": sum(d["kind"] not in ("control", "pyramids") and d["seed"] is None for d in sets),
            "seeds": sum(d["seed"] is not None for d in sets)}


def explorer_section(explorer_data: dict | None = None) -> dict | None:
    """The data of ``templates/explorer.html``, or None when the explorer is switched off.

    Parameters
    ----------
    explorer_data : the explorer's data (:func:`roughlight.report.explorer.explorer_data`, as rule
        ``explorer_data`` writes it), or None.

    Returns
    -------
    dict: ``index`` (JSON text), ``data`` (base64), ``script`` (the JavaScript), ``scripts`` (the texts the page's
    Content-Security-Policy allows), ``held`` (counts by sort), ``left_out`` (what the budget left out, with the
    kinds' names), ``bytes``, ``budget``, ``views`` (views a sweep), ``azimuths``, ``elevations`` (their count).
    """
    data = explorer_data
    if data is None:
        return None
    script = explorer_script()
    left_out = [{**g, "name": KIND_NAMES.get(g["kind"], g["kind"])} for g in data["left_out"]]
    return {"index": _index_json(data), "data": data["data"], "script": script, "scripts": [script],
            "held": _held(data), "left_out": left_out, "bytes": data["bytes"], "budget": data["budget"],
            "azimuths": len(data["azimuths"]), "elevations": len(data["elevations"]),
            "views": len(data["azimuths"]) * len(data["elevations"])}


SECTION = Section("explorer", explorer_section, "explorer.html", title="Hemisphere explorer",
                  switch="report.explorer.enabled", inputs={"explorer_data": "results/analysis/explorer_data.json"})
