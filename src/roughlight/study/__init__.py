"""The study: the configuration and the settings it implies, one sweep's table and the study table, and how
rows of it are selected. Imports ``render`` and ``surfaces``."""
