"""Analysis of the study table: lobes, the diffuse parts, the thesis's Tables 1-2, grid GLMs, analytic models,
share laws, random ensembles, and the analysis rules' steps. Imports ``study`` and the stages below it."""
