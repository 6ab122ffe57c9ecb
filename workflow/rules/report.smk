# Analysis and report (issue #5): results/study.parquet -> results/analysis/*, results/figures/*.png
# and the self-contained reports/roughlight_report.html. Settings under `report:` in the config
# (all optional; defaults and allowed values in workflow/schemas/config.schema.yaml).
import os

REPORT_FIGURES = [
    "fig19_topdown",
    "fig21_specular_truncation",
    "fig23_forward_models",
    "fig24_reflecting_areas",
    "fig25_back_models",
    "fig26_specular_aspect",
    "fig27_diffuse_plate",
    "fig28_diffuse_truncation",
    "fig29_diffuse_aspect",
    "lobe_geometry",
    "diffuse_parts",
    "glm_diagnostics",
    "model_fits",
    "hapke",
    "timings",
]
REPORT_RENDERED_FIGURES = [
    "fig09_shadows",
    "fig10_grazing",
    "fig13_tops",
    "fig17_clipping",
    "fig20_plate_incidence",
]
REPORT_BENCHMARKS = [
    "results/benchmarks/speed_accuracy.png",
    "results/benchmarks/speed_accuracy.parquet",
]


# settings of the report rules: the `report:` section of the config over the defaults (plain types)
REPORT_SETTINGS = dict(config["report"])  # validated, defaults filled (workflow/schemas/config.schema.yaml)
REPORT_SETTINGS["table_aspects"] = [float(a) for a in REPORT_SETTINGS["table_aspects"]]
REPORT_LIGHTING = rl_config.lighting_from_config(config).as_dict()
REPORT_RENDER = rl_config.render_settings_from_config(config)
# the optional speed/accuracy benchmark: whichever files exist when the workflow starts
REPORT_BENCHMARK_INPUTS = [path for path in REPORT_BENCHMARKS if os.path.exists(path)]
# the optional stability measurements (`make bench`): all three files, or none
REPORT_STABILITY = [
    "results/stability/stability.png",
    "results/stability/safe_domain.csv",
    "results/stability/stability.parquet",
]
REPORT_STABILITY_INPUTS = REPORT_STABILITY if all(os.path.exists(p) for p in REPORT_STABILITY) else []
REPORT_FIGURE_FILES = [f"results/figures/{stem}.png" for stem in REPORT_FIGURES + REPORT_RENDERED_FIGURES]


rule report_tables:
    input:
        study="results/study.parquet",
    output:
        lobes="results/analysis/lobes_arc.parquet",
        hemisphere="results/analysis/lobes_hemisphere.parquet",
        diffuse_parts=report(
            "results/analysis/diffuse_three_part.csv",
            caption="../report/diffuse_three_part.rst",
            category="Tables",
            subcategory="Diffuse",
        ),
        diffuse_levels="results/analysis/diffuse_levels.csv",
        exact="results/analysis/exact_peaks.csv",
        thesis_tables=report(
            "results/analysis/thesis_tables.csv",
            caption="../report/thesis_tables.rst",
            category="Tables",
            subcategory="Thesis Tables 1-2",
        ),
        bootstrap=report(
            "results/analysis/thesis_tables_bootstrap.csv",
            caption="../report/thesis_tables_bootstrap.rst",
            category="Tables",
            subcategory="Thesis Tables 1-2",
        ),
        sine=report(
            "results/analysis/sine_refits.csv",
            caption="../report/sine_refits.rst",
            category="Tables",
            subcategory="Thesis Tables 1-2",
        ),
        areas="results/analysis/reflecting_areas.csv",
        timings="results/analysis/render_timings.csv",
        summary="results/analysis/study_summary.json",
    params:
        settings=REPORT_SETTINGS,
        lighting=REPORT_LIGHTING,
    log:
        "results/logs/report/tables.log",
    threads: 1
    conda:
        "../../envs/study.yaml"
    resources:
        mem_mb=4096,
    script:
        "../scripts/analysis_tables.py"


rule report_glm:
    input:
        lobes="results/analysis/lobes_arc.parquet",
        diffuse_levels="results/analysis/diffuse_levels.csv",
    output:
        summary=report(
            "results/analysis/glm_summary.csv",
            caption="../report/glm_summary.rst",
            category="Tables",
            subcategory="Beyond the thesis",
        ),
        coefficients=report(
            "results/analysis/glm_coefficients.csv",
            caption="../report/glm_coefficients.rst",
            category="Tables",
            subcategory="Beyond the thesis",
        ),
        diagnostics="results/analysis/glm_diagnostics.csv",
        messages="results/analysis/glm_messages.json",
    params:
        settings=REPORT_SETTINGS,
    log:
        "results/logs/report/glm.log",
    threads: 1
    conda:
        "../../envs/study.yaml"
    resources:
        mem_mb=1024,
    script:
        "../scripts/analysis_glm.py"


rule report_models:
    input:
        study="results/study.parquet",
    output:
        fits="results/analysis/model_fits.parquet",
        summary=report(
            "results/analysis/model_fits_summary.csv",
            caption="../report/model_fits_summary.rst",
            category="Tables",
            subcategory="Beyond the thesis",
        ),
    params:
        settings=REPORT_SETTINGS,
        lighting=REPORT_LIGHTING,
    log:
        "results/logs/report/models.log",
    threads: 1
    conda:
        "../../envs/study.yaml"
    resources:
        mem_mb=4096,
    script:
        "../scripts/analysis_models.py"


rule report_figures:
    input:
        study="results/study.parquet",
        lobes="results/analysis/lobes_arc.parquet",
        diffuse_parts="results/analysis/diffuse_three_part.csv",
        sine="results/analysis/sine_refits.csv",
        exact="results/analysis/exact_peaks.csv",
        areas="results/analysis/reflecting_areas.csv",
        timings="results/analysis/render_timings.csv",
        glm_summary="results/analysis/glm_summary.csv",
        glm_diagnostics="results/analysis/glm_diagnostics.csv",
        fits="results/analysis/model_fits.parquet",
    output:
        fig19_topdown=report(
            "results/figures/fig19_topdown.png",
            caption="../report/fig19_topdown.rst",
            category="Figures",
            subcategory="Specular",
        ),
        fig21_specular_truncation=report(
            "results/figures/fig21_specular_truncation.png",
            caption="../report/fig21_specular_truncation.rst",
            category="Figures",
            subcategory="Specular",
        ),
        fig23_forward_models=report(
            "results/figures/fig23_forward_models.png",
            caption="../report/fig23_forward_models.rst",
            category="Figures",
            subcategory="Specular",
        ),
        fig24_reflecting_areas=report(
            "results/figures/fig24_reflecting_areas.png",
            caption="../report/fig24_reflecting_areas.rst",
            category="Figures",
            subcategory="Specular",
        ),
        fig25_back_models=report(
            "results/figures/fig25_back_models.png",
            caption="../report/fig25_back_models.rst",
            category="Figures",
            subcategory="Specular",
        ),
        fig26_specular_aspect=report(
            "results/figures/fig26_specular_aspect.png",
            caption="../report/fig26_specular_aspect.rst",
            category="Figures",
            subcategory="Specular",
        ),
        fig27_diffuse_plate=report(
            "results/figures/fig27_diffuse_plate.png",
            caption="../report/fig27_diffuse_plate.rst",
            category="Figures",
            subcategory="Diffuse",
        ),
        fig28_diffuse_truncation=report(
            "results/figures/fig28_diffuse_truncation.png",
            caption="../report/fig28_diffuse_truncation.rst",
            category="Figures",
            subcategory="Diffuse",
        ),
        fig29_diffuse_aspect=report(
            "results/figures/fig29_diffuse_aspect.png",
            caption="../report/fig29_diffuse_aspect.rst",
            category="Figures",
            subcategory="Diffuse",
        ),
        lobe_geometry=report(
            "results/figures/lobe_geometry.png",
            caption="../report/lobe_geometry.rst",
            category="Figures",
            subcategory="Beyond the thesis",
        ),
        diffuse_parts=report(
            "results/figures/diffuse_parts.png",
            caption="../report/diffuse_parts.rst",
            category="Figures",
            subcategory="Diffuse",
        ),
        glm_diagnostics=report(
            "results/figures/glm_diagnostics.png",
            caption="../report/glm_diagnostics.rst",
            category="Figures",
            subcategory="Beyond the thesis",
        ),
        model_fits=report(
            "results/figures/model_fits.png",
            caption="../report/model_fits.rst",
            category="Figures",
            subcategory="Beyond the thesis",
        ),
        hapke=report(
            "results/figures/hapke.png",
            caption="../report/hapke.rst",
            category="Figures",
            subcategory="Beyond the thesis",
        ),
        timings=report(
            "results/figures/timings.png",
            caption="../report/timings.rst",
            category="Figures",
            subcategory="Provenance",
        ),
    params:
        settings=REPORT_SETTINGS,
    log:
        "results/logs/report/figures.log",
    threads: 1
    conda:
        "../../envs/study.yaml"
    resources:
        mem_mb=4096,
    script:
        "../scripts/figures.py"


rule report_render_figures:
    output:
        plates="results/analysis/plate_sweeps.parquet",
        fig09_shadows=report(
            "results/figures/fig09_shadows.png",
            caption="../report/fig09_shadows.rst",
            category="Figures",
            subcategory="Pictures",
        ),
        fig10_grazing=report(
            "results/figures/fig10_grazing.png",
            caption="../report/fig10_grazing.rst",
            category="Figures",
            subcategory="Pictures",
        ),
        fig13_tops=report(
            "results/figures/fig13_tops.png",
            caption="../report/fig13_tops.rst",
            category="Figures",
            subcategory="Pictures",
        ),
        fig17_clipping=report(
            "results/figures/fig17_clipping.png",
            caption="../report/fig17_clipping.rst",
            category="Figures",
            subcategory="Specular",
        ),
        fig20_plate_incidence=report(
            "results/figures/fig20_plate_incidence.png",
            caption="../report/fig20_plate_incidence.rst",
            category="Figures",
            subcategory="Specular",
        ),
    params:
        lighting=REPORT_LIGHTING,
        render=REPORT_RENDER,
        elevation_step=float(config["sweep"]["elevation_step"]),
        incidences=[0, 10, 20, 30, 40, 50, 60, 70, 80, 90],
        lights=[127, 255],
    log:
        "results/logs/report/render_figures.log",
    threads: 1
    conda:
        "../../envs/render.yaml"
    resources:
        mem_mb=2048,
    script:
        "../scripts/render_figures.py"


rule report_html:
    input:
        study="results/study.parquet",
        lobes="results/analysis/lobes_arc.parquet",
        hemisphere="results/analysis/lobes_hemisphere.parquet",
        diffuse_parts="results/analysis/diffuse_three_part.csv",
        exact="results/analysis/exact_peaks.csv",
        thesis_tables="results/analysis/thesis_tables.csv",
        bootstrap="results/analysis/thesis_tables_bootstrap.csv",
        sine="results/analysis/sine_refits.csv",
        timings="results/analysis/render_timings.csv",
        summary="results/analysis/study_summary.json",
        glm_summary="results/analysis/glm_summary.csv",
        glm_coefficients="results/analysis/glm_coefficients.csv",
        glm_messages="results/analysis/glm_messages.json",
        fits="results/analysis/model_fits.parquet",
        fits_summary="results/analysis/model_fits_summary.csv",
        figures=REPORT_FIGURE_FILES,
        benchmarks=REPORT_BENCHMARK_INPUTS,
        stability=REPORT_STABILITY_INPUTS,
    output:
        report(
            "reports/roughlight_report.html",
            caption="../report/roughlight_report.rst",
            category="Report",
        ),
    params:
        config=config,
        settings=REPORT_SETTINGS,
    log:
        "results/logs/report/html.log",
    threads: 1
    conda:
        "../../envs/study.yaml"
    resources:
        mem_mb=1024,
    script:
        "../scripts/report_html.py"
