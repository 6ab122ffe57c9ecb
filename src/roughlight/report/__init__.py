"""The report: its figures, the registry of figures and captions, and the self-contained HTML page. The top
stage: it may import every other."""
