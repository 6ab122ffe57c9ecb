"""The page's "Settings and provenance": render timings, the settings and configuration as YAML, package versions,
inputs and what the sweeps were rendered on (``templates/provenance.html``)."""

from __future__ import annotations

import datetime as _dt
import hashlib
import importlib.metadata
import platform
from pathlib import Path

import numpy as np
import pandas as pd

from ...surfaces.surface import aspect_label
from ..page_templates import frame_or_none, section_figures
from ..registry import Section, figures


def _plain(obj):
    """Config values as plain YAML-safe types (Snakemake's Namedlist/dict subclasses)."""
    if isinstance(obj, dict):
        return {str(k): _plain(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_plain(v) for v in obj]
    if isinstance(obj, (np.floating, np.integer)):
        return obj.item()
    return obj


def package_versions(names=("roughlight", "numpy", "pandas", "pyarrow", "scipy", "statsmodels", "matplotlib",
                            "seaborn", "shapely", "trimesh", "pyrender2", "PyOpenGL", "snakemake")) -> dict:
    """Installed versions of the packages the study uses (missing ones are 'not installed')."""
    out = {"python": platform.python_version()}
    for name in names:
        try:
            out[name] = importlib.metadata.version(name)
        except importlib.metadata.PackageNotFoundError:
            out[name] = "not installed"
    return out


def file_provenance(path) -> dict:
    """Size, modification time and SHA-256 of a file."""
    p = Path(path)
    h = hashlib.sha256()
    with open(p, "rb") as fh:
        for chunk in iter(lambda: fh.read(1 << 20), b""):
            h.update(chunk)
    st = p.stat()
    return {"path": str(path), "bytes": st.st_size,
            "modified": _dt.datetime.fromtimestamp(st.st_mtime, _dt.UTC).isoformat(timespec="seconds"),
            "sha256": h.hexdigest()}


def provenance_section(render_timings: pd.DataFrame | None = None, study_summary: dict | None = None,
                       figures: dict | None = None, config=None, provenance: dict | None = None) -> dict:
    """"Settings and provenance": timings, settings and configuration as YAML, package versions (``provenance["versions"]``,
    else those installed), inputs, and what the sweeps were rendered on (``provenance["renderers"]``: the GL
    renderer, OpenGL version and platform of each, :func:`roughlight.study.tables.renderers`)."""
    import yaml

    provenance = provenance or {}
    timings = frame_or_none(render_timings)
    if timings is not None:
        timings = timings.copy()
        timings["aspect"] = timings["aspect"].map(aspect_label)
    settings, inputs = provenance.get("settings"), provenance.get("inputs")
    versions = provenance.get("versions") or package_versions()
    return {
        "timings_summary": (study_summary or {}).get("timings") or {}, "timings": timings,
        "figures": section_figures("provenance", figures or {}),
        "settings": yaml.safe_dump(settings, sort_keys=False) if settings else None,
        "config": yaml.safe_dump(_plain(config), sort_keys=False) if config else None,
        "versions": pd.DataFrame(sorted(versions.items()), columns=["package", "version"]),
        "inputs": pd.DataFrame(inputs) if inputs else None,
        "renderers": list(provenance.get("renderers") or []),
    }


SECTION = Section("provenance", provenance_section, "provenance.html", title="Settings and provenance",
                  inputs={"study": "results/study.parquet", "render_timings": "results/analysis/render_timings.csv",
                          "study_summary": "results/analysis/study_summary.json",
                          "figures": tuple(f.path for f in figures(section="provenance"))})
