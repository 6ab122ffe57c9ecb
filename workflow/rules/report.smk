# Analysis and report: results/study.parquet -> results/analysis/*, results/figures/*.png and the
# self-contained reports/roughlight_report.html. Settings under `report:` in the config (defaults and
# allowed values in workflow/schemas/config.schema.yaml). The figures are roughlight.report.registry.FIGURES:
# each rule's outputs, the figure scripts and the HTML page are made from that one list; each
# figure's caption is workflow/report/{name}.rst. One name per output: a table's name, as a rule's output and as
# any rule's input, is its file's stem; a chart's is its stem and _png (rule report_html hands every input to
# the page's sections by these names; each section declares what it reads: roughlight.report.sections).


rule analysis_tables:
    input:
        study="results/study.parquet",
    output:
        lobes_arc="results/analysis/lobes_arc.parquet",
        lobes_hemisphere="results/analysis/lobes_hemisphere.parquet",
        diffuse_three_part=report(
            "results/analysis/diffuse_three_part.csv",
            caption="../report/diffuse_three_part.rst",
            category="Tables",
            subcategory="Diffuse",
        ),
        diffuse_levels="results/analysis/diffuse_levels.csv",
        exact_peaks="results/analysis/exact_peaks.csv",
        thesis_tables=report(
            "results/analysis/thesis_tables.csv",
            caption="../report/thesis_tables.rst",
            category="Tables",
            subcategory="Thesis Tables 1-2",
        ),
        thesis_tables_bootstrap=report(
            "results/analysis/thesis_tables_bootstrap.csv",
            caption="../report/thesis_tables_bootstrap.rst",
            category="Tables",
            subcategory="Thesis Tables 1-2",
        ),
        sine_refits=report(
            "results/analysis/sine_refits.csv",
            caption="../report/sine_refits.rst",
            category="Tables",
            subcategory="Thesis Tables 1-2",
        ),
        reflecting_areas="results/analysis/reflecting_areas.csv",
        implied_scales="results/analysis/implied_scales.csv",
        tables_at_implied_scale="results/analysis/tables_at_implied_scale.csv",
        render_timings="results/analysis/render_timings.csv",
        study_summary="results/analysis/study_summary.json",
    log:
        "results/logs/report/tables.log",
    benchmark:
        "results/logs/report/tables.benchmark.tsv"
    priority: PRIORITY_STUDY_CHAIN
    conda:
        "../../envs/study.yaml"
    threads: 1
    resources:
        mem_mb=4096,
    params:
        settings=report_keys(
            "table_aspects", "table_incidence", "lobe_halfwidth", "exact_check"
        ),
        lighting=lighting_params,
    script:
        "../scripts/analysis_tables.py"


rule analysis_glm:
    input:
        lobes_arc="results/analysis/lobes_arc.parquet",
        diffuse_levels="results/analysis/diffuse_levels.csv",
    output:
        glm_summary=report(
            "results/analysis/glm_summary.csv",
            caption="../report/glm_summary.rst",
            category="Tables",
            subcategory="Beyond the thesis",
        ),
        glm_coefficients=report(
            "results/analysis/glm_coefficients.csv",
            caption="../report/glm_coefficients.rst",
            category="Tables",
            subcategory="Beyond the thesis",
        ),
        glm_diagnostics="results/analysis/glm_diagnostics.csv",
        glm_messages="results/analysis/glm_messages.json",
        share_laws=report(
            "results/analysis/share_laws.csv",
            caption="../report/share_laws.rst",
            category="Tables",
            subcategory="Beyond the thesis",
        ),
    log:
        "results/logs/report/glm.log",
    benchmark:
        "results/logs/report/glm.benchmark.tsv"
    priority: PRIORITY_STUDY_CHAIN
    conda:
        "../../envs/study.yaml"
    threads: 1
    resources:
        mem_mb=1024,
    params:
        settings=report_keys("collinearity_limit"),
        lighting=lighting_params,
    script:
        "../scripts/analysis_glm.py"


rule analysis_models:
    input:
        study="results/study.parquet",
    output:
        model_fits="results/analysis/model_fits.parquet",
        model_fits_summary=report(
            "results/analysis/model_fits_summary.csv",
            caption="../report/model_fits_summary.rst",
            category="Tables",
            subcategory="Beyond the thesis",
        ),
    log:
        "results/logs/report/models.log",
    benchmark:
        "results/logs/report/models.benchmark.tsv"
    priority: PRIORITY_STUDY_CHAIN
    conda:
        "../../envs/study.yaml"
    threads: 1
    resources:
        mem_mb=4096,
    params:
        settings=report_keys("hapke_max_phase"),
        lighting=lighting_params,
    script:
        "../scripts/analysis_models.py"


# input names are the figure functions' parameter names (workflow/scripts/figures.py gives each
# figure the tables it asks for)
rule figures:
    input:
        study="results/study.parquet",
        lobes_arc="results/analysis/lobes_arc.parquet",
        diffuse_three_part="results/analysis/diffuse_three_part.csv",
        sine_refits="results/analysis/sine_refits.csv",
        exact_peaks="results/analysis/exact_peaks.csv",
        reflecting_areas="results/analysis/reflecting_areas.csv",
        render_timings="results/analysis/render_timings.csv",
        glm_summary="results/analysis/glm_summary.csv",
        glm_diagnostics="results/analysis/glm_diagnostics.csv",
        model_fits="results/analysis/model_fits.parquet",
    output:
        **figure_outputs("figures"),
    log:
        "results/logs/report/figures.log",
    benchmark:
        "results/logs/report/figures.benchmark.tsv"
    priority: PRIORITY_STUDY_CHAIN
    conda:
        "../../envs/study.yaml"
    threads: 1
    resources:
        mem_mb=4096,
    params:
        settings=report_keys("table_aspects", "table_incidence", "hapke_max_phase"),
    script:
        "../scripts/figures.py"


rule render_figures:
    output:
        **figure_outputs("render_figures"),
        plates="results/analysis/plate_sweeps.parquet",
    log:
        "results/logs/report/render_figures.log",
    benchmark:
        "results/logs/report/render_figures.benchmark.tsv"
    conda:
        "../../envs/render.yaml"
    threads: 1
    resources:
        mem_mb=2048,
    params:
        gl=gl_params,
        lighting=lighting_params,
        render=render_params,
        elevation_step=float(config["sweep"]["elevation_step"]),
        incidence=table_incidence_param,
        incidences=config["report"]["figure_incidences"],
        lights=config["report"]["figure_lights"],
    script:
        "../scripts/render_figures.py"


# the random-roughness claim's lobes and their search discs, from geometry and the regular surfaces alone
# (roughlight.analysis.steps.claim_discs)
rule claim_discs:
    input:
        study="results/study.parquet",
    output:
        random_claim_geometry="results/analysis/random_claim_geometry.csv",
    log:
        "results/logs/report/claim_discs.log",
    benchmark:
        "results/logs/report/claim_discs.benchmark.tsv"
    priority: PRIORITY_STUDY_CHAIN
    conda:
        "../../envs/study.yaml"
    threads: 1
    resources:
        mem_mb=2048,
    params:
        lighting=lighting_params,
    script:
        "../scripts/claim_discs.py"


# what the claim's design reads of its pilots, each ensemble's pooled readings: from its pilot tiles (rule
# claim_sweeps), or registered (claims.registered_pilots, written by `make claim-pilots`) where the ensemble's
# pilots were measured with its own settings (roughlight.study.pilots)
rule claim_pilots:
    input:
        pilots=claim_ensemble_folders("pilots"),
        geometry="results/analysis/random_claim_geometry.csv",
        registered=registered_pilots_file,
    output:
        random_claim_pilots="results/analysis/random_claim_pilots.csv",
    log:
        "results/logs/report/claim_pilots.log",
    benchmark:
        "results/logs/report/claim_pilots.benchmark.tsv"
    priority: PRIORITY_STUDY_CHAIN
    conda:
        "../../envs/study.yaml"
    threads: 1
    resources:
        mem_mb=1024,
    params:
        ensembles=pilot_keys,
        sweep=sweep_params,
    script:
        "../scripts/claim_pilots.py"


# the claim's design: margins, the family and the seeds each test needs, from the regular surfaces, the exact
# reference and the pilots' readings (rule claim_pilots) alone (roughlight.analysis.steps.claim_design): it
# reads no tested tile
rule claim_design:
    input:
        study="results/study.parquet",
        pilots="results/analysis/random_claim_pilots.csv",
        geometry="results/analysis/random_claim_geometry.csv",
        claim_grid=claim_grid_file,
    output:
        random_claim_design="results/analysis/random_claim_design.csv",
        random_claim_margins="results/analysis/random_claim_margins.csv",
        random_claim_errors="results/analysis/random_claim_errors.csv",
        random_claim_grid="results/analysis/random_claim_grid.csv",
    log:
        "results/logs/report/claim_design.log",
    benchmark:
        "results/logs/report/claim_design.benchmark.tsv"
    priority: PRIORITY_STUDY_CHAIN
    conda:
        "../../envs/study.yaml"
    threads: 1
    resources:
        mem_mb=2048,
    params:
        claims=claim_settings,
        sweep=sweep_params,
    script:
        "../scripts/claim_design.py"


rule analysis_random:
    input:
        study="results/study.parquet",
        claims=claim_ensemble_folders("tested"),
        geometry="results/analysis/random_claim_geometry.csv",
        design="results/analysis/random_claim_design.csv",
        margins="results/analysis/random_claim_margins.csv",
        third_round=registered_round_file("third"),
        fourth_round=registered_round_file("fourth"),
        fifth_round=registered_round_file("fifth"),
        sixth_round=registered_round_file("sixth"),
        seventh_round=registered_round_file("seventh"),
        eighth_round=registered_round_file("eighth"),
    output:
        random_statistics="results/analysis/random_statistics.parquet",
        random_ensembles=report(
            "results/analysis/random_ensembles.csv",
            caption="../report/random_statistics.rst",
            category="Tables",
            subcategory="Random roughness",
        ),
        random_seeds_needed="results/analysis/random_seeds_needed.csv",
        random_model_fits="results/analysis/random_model_fits.parquet",
        random_claims_round2="results/analysis/random_claims_round2.csv",
        random_claims_untaken="results/analysis/random_claims_untaken.csv",
        random_claims=report(
            "results/analysis/random_claims.csv",
            caption="../report/random_claims.rst",
            category="Tables",
            subcategory="Random roughness",
        ),
        random_ensembles_png=report(
            "results/figures/random_ensembles.png",
            caption="../report/random_ensembles.rst",
            category="Figures",
            subcategory="Random roughness",
        ),
        random_maps_png=report(
            "results/figures/random_maps.png",
            caption="../report/random_maps.rst",
            category="Figures",
            subcategory="Random roughness",
        ),
    log:
        "results/logs/report/random.log",
    benchmark:
        "results/logs/report/random.benchmark.tsv"
    priority: PRIORITY_STUDY_CHAIN
    conda:
        "../../envs/study.yaml"
    threads: 1
    resources:
        mem_mb=4096,
    params:
        settings=report_keys("lobe_halfwidth", "hapke_max_phase"),
        lighting=lighting_params,
        claims=claim_settings,
        sweep=sweep_params,
        measured=claim_measurement_params,
    script:
        "../scripts/analysis_random.py"


# every measured view of the study's surfaces, packed for the report's hemisphere explorer (report.explorer)
rule explorer_data:
    input:
        study="results/study.parquet",
    output:
        "results/analysis/explorer_data.json",
    log:
        "results/logs/report/explorer_data.log",
    benchmark:
        "results/logs/report/explorer_data.benchmark.tsv"
    conda:
        "../../envs/study.yaml"
    threads: 1
    resources:
        mem_mb=1024,
    params:
        budget=explorer_budget,
    script:
        "../scripts/explorer_data.py"


rule report_html:
    input:
        unpack(report_inputs),
    output:
        report(
            "reports/roughlight_report.html",
            caption="../report/roughlight_report.rst",
            category="Report",
        ),
    log:
        "results/logs/report/html.log",
    benchmark:
        "results/logs/report/html.benchmark.tsv"
    conda:
        "../../envs/study.yaml"
    threads: 1
    resources:
        mem_mb=1024,
    params:
        config=config,
        settings=report_settings,
        plan=measurement_plan,
        surface_settings=random_surface_settings,
        followed=followed_params,
        page_code=page_code,
    script:
        "../scripts/report_html.py"
